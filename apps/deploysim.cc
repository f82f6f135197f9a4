// The deploysim executable: the command line of deploysim/cli/app.h.

#include "deploysim/cli/app.h"

int main(int argc, char** argv) { return deploysim::cli::Main(argc, argv); }
