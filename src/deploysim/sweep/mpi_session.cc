#include "deploysim/sweep/mpi_session.h"

#include <cstdint>
#include <cstdlib>
#include <stdexcept>

#ifdef DEPLOYSIM_WITH_MPI
#include <mpi.h>
#endif

namespace deploysim::sweep {

namespace {

bool LaunchedByMpi() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_SIZE"}) {
    if (std::getenv(var) != nullptr) return true;
  }
  return false;
}

#ifdef DEPLOYSIM_WITH_MPI
void Check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI error in ") + what);
}
#endif

}  // namespace

bool MpiBuilt() {
#ifdef DEPLOYSIM_WITH_MPI
  return true;
#else
  return false;
#endif
}

std::string MpiExecutable() {
#ifdef DEPLOYSIM_MPIEXEC
  return DEPLOYSIM_MPIEXEC;
#else
  return "";
#endif
}

MpiSession::MpiSession([[maybe_unused]] int* argc, [[maybe_unused]] char*** argv) {
#ifdef DEPLOYSIM_WITH_MPI
  if (!LaunchedByMpi()) return;
  int provided = 0;
  Check(MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  active_ = true;
  Check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
  Check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  MPI_Comm node;
  Check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node),
        "MPI_Comm_split_type");
  Check(MPI_Comm_size(node, &local_size_), "MPI_Comm_size");
  MPI_Comm_free(&node);
#else
  (void)LaunchedByMpi;
#endif
}

MpiSession::~MpiSession() {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_) MPI_Finalize();
#endif
}

bool MpiSession::AllTrue(bool local) const {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_) {
    int in = local ? 1 : 0;
    int out = 0;
    Check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
    return out == 1;
  }
#endif
  return local;
}

std::uint64_t MpiSession::Sum(std::uint64_t local) const {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_) {
    unsigned long long in = local, out = 0;
    Check(MPI_Allreduce(&in, &out, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD),
          "MPI_Allreduce");
    return out;
  }
#endif
  return local;
}

std::vector<char> MpiSession::GatherToRoot(const std::vector<char>& local) const {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_) {
    // Sizes first, then the blocks (MPI counts are ints: at most 2 GiB in total).
    if (local.size() > static_cast<std::size_t>(INT32_MAX)) {
      throw std::runtime_error("MPI gather: more than 2 GiB of results on one rank");
    }
    const int n = static_cast<int>(local.size());
    std::vector<int> counts(static_cast<std::size_t>(size_));
    Check(MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::vector<int> displs(static_cast<std::size_t>(size_), 0);
    std::vector<char> all;
    if (rank_ == 0) {
      long long total = 0;
      for (int r = 0; r < size_; ++r) {
        displs[static_cast<std::size_t>(r)] = static_cast<int>(total);
        total += counts[static_cast<std::size_t>(r)];
      }
      if (total > INT32_MAX) throw std::runtime_error("MPI gather: more than 2 GiB of results");
      all.resize(static_cast<std::size_t>(total));
    }
    Check(MPI_Gatherv(local.data(), n, MPI_CHAR, all.data(), counts.data(), displs.data(), MPI_CHAR,
                      0, MPI_COMM_WORLD),
          "MPI_Gatherv");
    return all;
  }
#endif
  return local;
}

void MpiSession::AbortIfParallel([[maybe_unused]] int exit_code) const {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, exit_code);
#endif
}

void MpiSession::Barrier() const {
#ifdef DEPLOYSIM_WITH_MPI
  if (active_) Check(MPI_Barrier(MPI_COMM_WORLD), "MPI_Barrier");
#endif
}

}  // namespace deploysim::sweep
