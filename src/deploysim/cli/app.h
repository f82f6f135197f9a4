#pragma once

/// The `deploysim` command line: subcommands simulate, analyze, sweep, crosscheck,
/// methods, report and view (`deploysim --help`). Exit codes: 0 done; 1 bad input or a
/// failed run (one line on stderr naming the file, key, value and rule); 3 simulate: the
/// integration did not reach the end; 4 crosscheck: the two models disagree; 130
/// interrupted (SIGINT).

namespace deploysim::cli {

/// Runs the command line `argv` (argv[0] the program) and returns the exit code.
int Main(int argc, char** argv);

}  // namespace deploysim::cli
