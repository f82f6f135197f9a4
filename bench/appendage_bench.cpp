// Flexible appendages: what a beam costs and how close its chain is to the beam.
//   A. the clamped chain's first two bending frequencies against Euler-Bernoulli's as
//      the segment count N doubles, with the observed order of convergence;
//   B. the cost per simulated second of a beam on a spinning hub against N: the whole
//      chain (every hinge a coordinate: its stiff high modes set the steps) and the chain
//      reduced to its first 2 clamped modes (modes: 2), with the linear nutation rate of
//      each run (the accuracy the reduction keeps).
//
// Usage: appendage_bench [--quick] [--markdown FILE]

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.h"
#include "deploysim/model/flexible_beam.h"
#include "deploysim/model/mass_properties.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile.h"

namespace {

using namespace deploysim;
using math::Vec3;

constexpr double kEI = 10.0, kMass = 0.5, kLength = 2.0;  // N m^2, kg/m, m

model::BeamSpec Boom(int segments, int modes) {
  model::BeamSpec s;
  s.name = "boom";
  s.root_point = Vec3(0.4, 0.0, 0.0);
  s.direction = Vec3::UnitX();
  s.length = kLength;
  s.mass_per_length = kMass;
  s.radius = 0.005;
  s.planes = {model::BeamPlane{Vec3::UnitY(), kEI}};
  s.damping_ratio = 0.01;
  s.segments = segments;
  s.modes = modes;
  return s;
}

/// A 50 kg hub (0.8 x 0.8 x 0.6 m) spinning at 10 rpm about z (its major axis) with 5 deg
/// of nutation, the boom bending out of the plane of rotation.
schedule::Profile BoomProfile(int segments, int modes, double until) {
  model::Model md;
  md.name = "boom_on_hub";
  md.kind = model::ModelKind::kHinged;
  md.hinged.hub.body.mass = 50.0;
  md.hinged.hub.body.inertia_cm = model::BoxInertia(50.0, Vec3(0.8, 0.8, 0.6));
  md.appendages = {model::AddBeam(md.hinged, Boom(segments, modes), "bench")};
  md.hinged = model::ValidatedHingedBody(md.hinged, "bench");
  model::Configuration c;
  c.name = "straight";
  c.hinge_angles = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(md.hinged.panels.size()));
  md.configurations = {c};
  schedule::Profile p;
  p.name = "boom_on_hub";
  p.source = "appendage_bench";
  p.model = md;
  p.mode = schedule::Mode::kGeometry;
  p.coupling = schedule::Coupling::kExact;
  p.initial.configuration = "straight";
  const double spin = 10.0 * 2.0 * M_PI / 60.0;
  p.initial.w_NB_B = Vec3(spin * std::tan(5.0 * M_PI / 180.0), 0.0, spin);
  p.hinges.resize(md.hinged.panels.size());
  schedule::SetAppendagePlans(md, p.hinges);
  p.start = 0.0;
  p.until = until;
  p.integrator.method = "rkmk-rkf78";
  p.integrator.rtol = 1e-10;
  p.integrator.atol = 1e-12;
  p.output.dt = 0.1;
  return p;
}

void ConvergenceTable(bench::Markdown& md) {
  md.Add(
      "### 9. Flexible beams: the chain against the Euler-Bernoulli cantilever\n\n"
      "The clamped chain of N rigid segments on spring hinges (model/flexible_beam.h: "
      "hinges at the middle of N equal elements, k = EI / l) for a uniform beam (L = 2 m, "
      "0.5 kg/m, EI = 10 N m^2, a thin section), its first two bending frequencies from the "
      "generalized eigenproblem of the chain's own mass matrix, against beta_1 L = 1.8751 and "
      "beta_2 L = 4.6941; the order is log2 of the error's ratio to the previous row's.\n\n"
      "| N | omega_1 error | order | omega_2 error | order |\n|---:|---:|---:|---:|---:|\n");
  double prev1 = 0.0, prev2 = 0.0;
  for (int n = 4; n <= 64; n *= 2) {
    model::HingedBody body;
    body.hub.body.mass = 1.0;
    body.hub.body.inertia_cm = math::Mat3::Identity();
    model::BeamSpec s = Boom(n, 0);
    s.radius = 1e-5;
    const model::Appendage a = model::AddBeam(body, s, "bench");
    const double e1 = a.chain_frequencies[0][0] / a.beam_frequencies[0][0] - 1.0;
    const double e2 = a.chain_frequencies[0][1] / a.beam_frequencies[0][1] - 1.0;
    if (prev1 == 0.0) {
      md.Printf("| %d | %.3e | | %.3e | |\n", n, e1, e2);
    } else {
      md.Printf("| %d | %.3e | %.3f | %.3e | %.3f |\n", n, e1, std::log2(prev1 / e1), e2,
                std::log2(prev2 / e2));
    }
    prev1 = e1;
    prev2 = e2;
  }
  md.Add("\n");
}

struct CostRow {
  int segments = 0, modes = 0, coordinates = 0;
  double simulated = 0.0, wall = 0.0, rate = 0.0;
  long steps = 0;
};

CostRow Cost(int segments, int modes, double until, int reps) {
  CostRow row;
  row.segments = segments;
  row.modes = modes;
  row.coordinates = modes > 0 ? modes : segments;
  row.simulated = until;
  run::MissionResult r;
  const bench::Timing t = bench::TimeCold(reps, [&] {
    // The profile is built inside: the chain's expansion and modes are part of the cost.
    r = run::RunMission(BoomProfile(segments, modes, until));
  });
  row.wall = t.median();
  row.steps = static_cast<long>(r.stats.steps);
  row.rate = r.outcome.linear.growth_rate;
  return row;
}

void CostTable(bench::Markdown& md, bool quick) {
  const int reps = quick ? 1 : 3;
  const double long_run = quick ? 60.0 : 600.0;
  std::vector<CostRow> rows;
  for (int n : quick ? std::vector<int>{5, 20} : std::vector<int>{5, 10, 20, 40}) {
    rows.push_back(Cost(n, 2, long_run, reps));
  }
  // The whole chain: its stiffest damped mode sets the steps (10 s: a 600 s run of 20
  // segments takes hours).
  for (int n : quick ? std::vector<int>{5} : std::vector<int>{5, 10}) {
    rows.push_back(Cost(n, 0, quick ? 2.0 : 10.0, 1));
  }
  md.Add(
      "### 10. Flexible beams: cost per simulated second against the segment count\n\n"
      "A 50 kg hub spinning at 10 rpm about its major axis with 5 deg of nutation and one "
      "boom (the beam of table 9, radius 5 mm, damping ratio 0.01, bending out of the plane "
      "of rotation): the chain reduced to its first 2 clamped modes (`modes: 2`), and the "
      "whole chain (every hinge a coordinate). rkmk-rkf78, rtol 1e-10, output every 0.1 s. "
      "The nutation rate is the linearized one of each run (the reduction's accuracy: the "
      "whole chain's is the reference). Target: 20 segments, 600 s in under 10 s.\n\n"
      "| N | coordinates | simulated [s] | wall [s] | wall per simulated s [ms] | steps | "
      "nutation rate [1/s] |\n|---:|---|---:|---:|---:|---:|---:|\n");
  for (const CostRow& r : rows) {
    md.Printf("| %d | %s | %.0f | %.3g | %.3g | %ld | %.6e |\n", r.segments,
              r.modes > 0 ? (std::to_string(r.modes) + " modes").c_str()
                          : (std::to_string(r.segments) + " hinges").c_str(),
              r.simulated, r.wall, 1e3 * r.wall / r.simulated, r.steps, r.rate);
  }
  for (const CostRow& r : rows) {
    if (r.segments == 20 && r.modes == 2 && r.simulated == 600.0) {
      md.Printf("\n20 segments, 600 s: %.3g s (target < 10 s: %s).\n", r.wall,
                r.wall < 10.0 ? "met" : "missed");
    }
  }
  md.Printf("\n%s\n", bench::TimingRule(reps,
                                        "builds the beam's chain and modes and runs the whole "
                                        "mission (samples, events, outcome) on one core")
                          .c_str());
  md.Printf("%s\n", bench::MachineLine().c_str());
}

}  // namespace

int main(int argc, char** argv) {
  const bench::Args args = bench::ParseArgs(argc, argv);
  if (!args.rest.empty()) {
    std::fprintf(stderr, "usage: appendage_bench [--quick] [--markdown FILE]\n");
    return 2;
  }
  bench::Markdown md;
  ConvergenceTable(md);
  CostTable(md, args.quick);
  md.Emit(args.markdown);
  return 0;
}
