#pragma once

/// The cross-check file (HDF5, readable by h5py, MATLAB h5read and h5dump), written
/// atomically (io::AtomicFile: on failure nothing is left at `path`). Layout: row-major
/// IEEE little-endian doubles, each dataset with string attributes `units` and
/// `description`; quaternions scalar first (w, x, y, z).
///
///   /time                         N      s
///   /reduced/{H_B,h_N,w_NB_B}     N x 3  kg m^2/s, kg m^2/s, rad/s
///   /reduced/q_NB                 N x 4  1
///   /reduced/flip_time            F      s
///   /simbody/{H_B,h_N,w_NB_B,q_NB}, /simbody/flip_time      (same units)
///   /simbody/hinge_angles, /simbody/hinge_rates  N x P     rad, rad/s (geometry mode)
///   /difference/H_B_relative      N      1     |dH_B| / |H_B(t0)|
///   /difference/attitude          N      rad   angle of q_reduced^-1 q_simbody
///   /difference/w_NB_B            N      rad/s |dw|
///   /analytic/flip_time           F'     s     (constant-inertia runs only)
/// Root attributes (strings): deploysim_version, schema ("deploysim-crosscheck 1"),
/// profile_name, profile_source, profile_text, accuracy, reduced_integrator, and the
/// summary numbers max_H_B_relative_difference, max_attitude_difference,
/// max_w_difference, max_flip_time_difference, simbody_momentum_drift,
/// reduced_momentum_drift, reduced_wall_seconds, simbody_wall_seconds.
///
/// Note: STYLE.md keeps HDF5 inside io; this writer is here because the crosscheck
/// result type lives here and io cannot depend on crosscheck. A generic "named datasets"
/// writer in io would let it move there.

#include <string>

#include "deploysim/crosscheck/crosscheck.h"

namespace deploysim::crosscheck {

/// Throws std::runtime_error naming `path` for I/O failures.
void WriteCrosscheckFile(const std::string& path, const CrosscheckResult& result);

}  // namespace deploysim::crosscheck
