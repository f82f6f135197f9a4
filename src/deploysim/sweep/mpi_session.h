#pragma once

/// Optional MPI (DEPLOYSIM_WITH_MPI builds; OpenMPI): `mpirun -np N deploysim sweep ...`
/// shards the cases over the ranks. Without MPI, or when the program was not started by
/// an MPI launcher, a session is a single process (rank 0 of 1) and every collective is
/// the identity, so callers need no #ifdefs.

#include <cstdint>
#include <string>
#include <vector>

namespace deploysim::sweep {

/// True when this build has MPI support.
bool MpiBuilt();

/// The mpiexec this build was configured with (empty without MPI).
std::string MpiExecutable();

/// MPI for the lifetime of the object (MPI_Init_thread with MPI_THREAD_FUNNELED: only the
/// thread that made the session calls MPI). Initializes MPI only in an MPI build and when
/// an MPI launcher started the process (OMPI_COMM_WORLD_SIZE, PMIX_RANK or PMI_SIZE is
/// set), so a plain `deploysim sweep` never touches MPI. At most one session per process.
class MpiSession {
 public:
  /// argc/argv may be null.
  MpiSession(int* argc, char*** argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  bool active() const { return active_; }
  int rank() const { return rank_; }
  int size() const { return size_; }
  /// Ranks on this node (for the default thread count); 1 when inactive.
  int local_size() const { return local_size_; }

  /// Logical AND over all ranks.
  bool AllTrue(bool local) const;
  /// Sum over all ranks, known to every rank.
  std::uint64_t Sum(std::uint64_t local) const;
  /// The byte blocks of all ranks, concatenated in rank order, at rank 0 (empty elsewhere).
  std::vector<char> GatherToRoot(const std::vector<char>& local) const;
  void Barrier() const;

  /// Ends the whole job (MPI_Abort with `exit_code`) when this session spans more than one
  /// rank; returns (doing nothing) otherwise. For an error that escapes on one rank: the
  /// other ranks would otherwise wait forever in the next collective. The caller prints
  /// its message first.
  void AbortIfParallel(int exit_code) const;

 private:
  bool active_ = false;
  int rank_ = 0;
  int size_ = 1;
  int local_size_ = 1;
};

}  // namespace deploysim::sweep
