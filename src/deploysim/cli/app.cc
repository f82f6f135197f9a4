// deploysim: the command-line front end (app.h). Parses, runs, reports; the only place
// that catches exceptions (one line on stderr, non-zero exit).

#include "deploysim/cli/app.h"

#include <fmt/format.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "deploysim/analysis/exact_flow.h"
#include "deploysim/analysis/work_estimate.h"
#include "deploysim/cli/python_tool.h"
#include "deploysim/cli/report.h"
#include "deploysim/io/atomic_file.h"
#include "deploysim/io/trajectory_file.h"
#include "deploysim/io/yaml_loader.h"
#include "deploysim/run/coupling_comparison.h"
#include "deploysim/run/mission.h"
#include "deploysim/schedule/profile_warnings.h"
#include "deploysim/version.h"
#ifdef DEPLOYSIM_HAVE_SWEEP
#include "deploysim/sweep/interrupt.h"
#include "deploysim/sweep/mpi_session.h"
#include "deploysim/sweep/parallel.h"
#include "deploysim/sweep/runner.h"
#include "deploysim/sweep/sweep_file.h"
#endif
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
#include "deploysim/crosscheck/crosscheck.h"
#include "deploysim/crosscheck/crosscheck_file.h"
#include "deploysim/crosscheck/free_hinge_crosscheck.h"
#include "deploysim/crosscheck/speed_study.h"
#endif

namespace {

using deploysim::run::MissionResult;

constexpr int kExitBadInput = 1;
constexpr int kExitIncomplete = 3;     // simulate: the integration did not reach the end
constexpr int kExitDisagree = 4;       // crosscheck: the two models disagree (CrosscheckVerdict)
constexpr int kExitInterrupted = 130;  // 128 + SIGINT, as shells report it

struct Overrides {
  std::optional<std::string> method, coupling, mode;
  std::optional<double> rtol, atol, step, dt, until;
};

// A numeric option's rule, checked on its text before CLI11 converts it, so that every
// option error is one short line "--dt: 1e-5x is not a number > 0" (CLI11's own
// messages take two lines and print DBL_MAX in full). Long values are cut.
CLI::Validator Number(const std::string& rule,
                      const std::function<bool(double)>& ok,
                      bool integer = false) {
  return CLI::Validator(
      [rule, ok, integer](std::string& text) -> std::string {
        const char* b = text.c_str();
        char* e = nullptr;
        errno = 0;
        const double v =
            integer ? static_cast<double>(std::strtoll(b, &e, 10)) : std::strtod(b, &e);
        if (e != b && *e == '\0' && errno == 0 && std::isfinite(v) && ok(v)) return {};
        const std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
        return shown + " is not " + (integer ? "an integer " : "a number ") + rule;
      },
      rule);
}

// An `integrator:` key's override (--rtol, --atol, --step): its range is the profile
// key's (schedule::IntegratorRuleViolated), stated there once.
CLI::Validator IntegratorNumber(const std::string& key) {
  using deploysim::schedule::IntegratorRuleViolated;
  const std::string must = IntegratorRuleViolated(key, std::nan(""));  // "must be ..."
  const std::string rule = must.substr(must.find(' ') + 1);            // "be ..."
  return CLI::Validator(
      [key](std::string& text) -> std::string {
        const char* b = text.c_str();
        char* e = nullptr;
        errno = 0;
        const double v = std::strtod(b, &e);
        const std::string shown = text.size() > 40 ? text.substr(0, 40) + "..." : text;
        if (e == b || *e != '\0' || errno != 0 || !std::isfinite(v)) {
          return shown + " is not a number";
        }
        const std::string violated = IntegratorRuleViolated(key, v);
        return violated.empty() ? std::string() : shown + ": " + violated;
      },
      rule.substr(rule.find(' ') + 1));
}

void AddOverrideOptions(CLI::App* cmd, Overrides& o) {
  cmd->add_option("--method", o.method, "integrator (see `deploysim methods`)");
  cmd->add_option("--rtol", o.rtol, "relative tolerance of adaptive integrators")
      ->check(IntegratorNumber("rtol"));
  cmd->add_option("--atol", o.atol, "absolute tolerance, relative to |H_B(0)|")
      ->check(IntegratorNumber("atol"));
  cmd->add_option("--step", o.step, "fixed step [s] (initial step for adaptive methods)")
      ->check(IntegratorNumber("step"));
  cmd->add_option("--dt", o.dt, "output sampling interval [s]")->check(Number("> 0", [](double v) {
    return v > 0.0;
  }));
  cmd->add_option("--until", o.until,
                  "end the run at this time [s] (a stage profile: in a hold stage, at a stage "
                  "end, or after its last stage, holding the last configuration)")
      ->check(Number("(finite)", [](double) { return true; }));
  cmd->add_option("--coupling", o.coupling, "quasi-rigid | exact");
  cmd->add_option("--mode", o.mode, "tensor | geometry");
}

// Legal inputs that are almost certainly not meant (schedule::ProfileWarnings), one line
// each on stderr; the trajectory file and the report carry them too.
void PrintWarnings(const deploysim::schedule::Profile& p) {
  for (const std::string& w : deploysim::schedule::ProfileWarnings(p)) {
    std::cerr << "deploysim: warning: " << w << "\n";
  }
}

std::shared_ptr<const deploysim::run::CompiledRun> Load(const std::string& path,
                                                        const Overrides& o) {
  deploysim::io::ProfileOverrides po;
  po.method = o.method;
  po.coupling = o.coupling;
  po.mode = o.mode;
  po.rtol = o.rtol;
  po.atol = o.atol;
  po.step = o.step;
  po.output_dt = o.dt;
  po.until = o.until;
  std::shared_ptr<const deploysim::run::CompiledRun> run = deploysim::io::LoadRun(path, po);
  PrintWarnings(run->profile());
  return run;
}

// A progress bar on a terminal. A run estimated to be long (analysis::kLongRunSeconds)
// says so first, and off a terminal prints a line at every tenth of the run instead;
// other runs are short and print nothing (sweeps have their own progress).
std::function<void(double)> Progress(bool quiet, const deploysim::run::CompiledRun& run) {
  if (quiet) return {};
  const deploysim::analysis::WorkEstimate& e = run.work();
  const bool long_run = e.seconds > deploysim::analysis::kLongRunSeconds;
  if (long_run) {
    std::cerr << "deploysim: a long run: " << deploysim::analysis::DescribeWork(e) << "\n";
  }
  if (isatty(fileno(stderr)) == 0) {
    if (!long_run) return {};
    auto next = std::make_shared<int>(1);
    const auto t0 = std::chrono::steady_clock::now();
    return [next, t0](double f) {
      if (f * 10.0 < *next) return;
      *next = static_cast<int>(f * 10.0) + 1;
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "deploysim: %3d%% of the run after %.0f s\n", static_cast<int>(f * 100),
                   s);
    };
  }
  return [](double f) {
    const int width = 40;
    const int filled = static_cast<int>(f * width);
    std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), static_cast<int>(f * 100));
    if (f >= 1.0) std::fprintf(stderr, "\r%*s\r", width + 8, "");
    std::fflush(stderr);
  };
}

// Refuses an output path that names one of the run's input files (the same file by
// another name included) or an existing thing that is not a regular file (a device, a
// FIFO, a folder): writing would replace it. Throws std::invalid_argument.
void RefuseOutputOver(const std::string& output, const std::vector<std::string>& inputs) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(output, ec);
  if (ec || !fs::exists(st)) return;
  if (!fs::is_regular_file(st)) {
    throw std::invalid_argument(output +
                                ": output exists and is not a regular file (rule: deploysim "
                                "writes only regular files; choose another output path)");
  }
  for (const std::string& in : inputs) {
    if (in.empty()) continue;
    std::error_code e2;
    if (fs::equivalent(output, in, e2) && !e2) {
      throw std::invalid_argument(output + ": output is the input file " + in +
                                  " (rule: an output never replaces an input of the run)");
    }
  }
}

// Runs f(); an error whose message does not start with `file` or one of `outputs` (e.g. a
// root solver's or FreeBodySolution's, which know no file) is rethrown as
// "<file>: <message>". Errors about an output (streamed while the run goes) name it already.
template <class F>
auto NamingFile(const std::string& file, F&& f, const std::vector<std::string>& outputs = {})
    -> decltype(f()) {
  try {
    return f();
  } catch (const std::exception& e) {
    const std::string m = e.what();
    if (m.rfind(file, 0) == 0) throw;
    for (const std::string& o : outputs) {
      if (!o.empty() && m.rfind(o + ":", 0) == 0) throw;
    }
    if (dynamic_cast<const std::invalid_argument*>(&e) != nullptr) {
      throw std::invalid_argument(file + ": " + m);
    }
    throw std::runtime_error(file + ": " + m);
  }
}

// Every value the command line sets. One set serves all subcommands: exactly one of them
// runs, and the options they share (the profile, -o, --csv, -q, the overrides) fill the
// same fields.
struct CommandLine {
  std::string profile_path, out_path;
  bool csv = false, quiet = false, json = false, compare = false;
  Overrides ov;
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
  double cc_accuracy = 1e-12;
  double cc_tolerance = deploysim::crosscheck::kDefaultAgreementTolerance;
  std::optional<double> cc_until;
  bool speed_study = false;
  std::string speed_csv;
  double cc_own_error = 0.0;
#endif
#ifdef DEPLOYSIM_HAVE_SWEEP
  std::string sweep_path;
  int sweep_threads = 0;
  bool resume = false;
#endif
};

// The subcommands, kept to ask after parsing which one the command line named.
struct Subcommands {
  CLI::App* sim = nullptr;
  CLI::App* ana = nullptr;
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
  CLI::App* cc = nullptr;
#endif
#ifdef DEPLOYSIM_HAVE_SWEEP
  CLI::App* swp = nullptr;
#endif
  CLI::App* meth = nullptr;
  CLI::App* rep = nullptr;
  CLI::App* view = nullptr;
};

// The top level: --version, one-line errors, exactly one subcommand, the examples.
void ConfigureApp(CLI::App& app) {
  app.set_version_flag("--version", deploysim::kBuildId);
  // Every command-line error on one line (subcommands inherit it).
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "deploysim: error: " + std::string(e.what()) + " (see deploysim --help)\n";
  });
  app.require_subcommand(1);
  app.footer(
      "Examples:\n"
      "  deploysim simulate deployment_profiles/smallsat_spring_deploy.yaml -o spring.h5\n"
      "      (free hinges: springs, dampers, latches; prints the deployment timeline)\n"
      "  deploysim simulate deployment_profiles/smallsat_three_stage.yaml -o out/smallsat.h5\n"
      "  deploysim simulate deployment_profiles/wing_nut.yaml --method exact -o wing_nut.h5\n"
      "  deploysim analyze deployment_profiles/minor_axis_flat_spin.yaml   (energy sink)\n"
      "  deploysim simulate deployment_profiles/spin_stabilized_tank.yaml -o tank.h5\n"
      "      (propellant slosh turns a minor-axis spin flat; appendages: docs/appendages.md)\n"
      "  deploysim simulate examples/long/explorer1.yaml -o explorer1.h5\n"
      "      (flexible whip antennas: Explorer 1's flat spin, about a minute)\n"
      "  deploysim analyze deployment_profiles/seed_satellite.yaml\n"
      "  deploysim analyze deployment_profiles/smallsat_three_stage.yaml --json\n"
      "  deploysim crosscheck deployment_profiles/smallsat_three_stage.yaml -o smallsat_cc.h5\n"
      "  deploysim sweep sweeps/smallsat_duration_spin.yaml -o smallsat_map.h5\n"
      "  deploysim methods\n"
      "  deploysim report deployment_profiles/smallsat_spring_deploy.yaml -o report.html\n"
      "  deploysim view spring.h5 -o spring.html   (3D viewer; open it in a browser)\n"
      "File formats: docs/file_formats.md. Plots: /usr/bin/python3 tools/plot_trajectory.py "
      "OUT.h5\n"
      "Exit status (every command): 0 done; 1 bad input or usage (one line on stderr, no "
      "output written); 3 simulate, report: the integration did not reach the end; 4 "
      "crosscheck: the models disagree; 5 report: a plot tool or the output failed; 130 "
      "interrupted (Ctrl-C).");
}

// The deployment profile argument of simulate, analyze and crosscheck.
void AddProfileArgument(CLI::App* cmd, std::string& profile_path) {
  cmd->add_option("profile", profile_path, "deployment profile (YAML)")->required();
}

CLI::App* AddSimulateCommand(CLI::App& app, CommandLine& cl) {
  CLI::App* sim =
      app.add_subcommand("simulate", "run a deployment profile and write its trajectory (HDF5)");
  AddProfileArgument(sim, cl.profile_path);
  sim->add_option("-o,--output", cl.out_path,
                  "output HDF5 file (default: <profile stem>.h5 in the current folder)");
  sim->add_flag("--csv", cl.csv, "also write <output>.csv");
  sim->add_flag("-q,--quiet", cl.quiet, "no progress bar and no summary");
  sim->add_flag("--compare-coupling", cl.compare,
                "also run the other coupling and report the difference (geometry mode)");
  AddOverrideOptions(sim, cl.ov);
  sim->footer(
      "Examples:\n"
      "  deploysim simulate deployment_profiles/wing_nut.yaml -o wing_nut.h5 --method rkf78 "
      "--rtol 1e-12\n"
      "  deploysim simulate deployment_profiles/smallsat_spring_deploy.yaml -o spring.h5\n"
      "  (a hinge profile: the deployment timeline is printed; the file holds the hinge events)");
  return sim;
}

CLI::App* AddAnalyzeCommand(CLI::App& app, CommandLine& cl) {
  CLI::App* ana =
      app.add_subcommand("analyze", "stability per stage, predicted flips, danger windows");
  AddProfileArgument(ana, cl.profile_path);
  ana->add_flag("--json", cl.json, "print JSON instead of the table");
  AddOverrideOptions(ana, cl.ov);
  ana->footer("Example: deploysim analyze deployment_profiles/seed_satellite.yaml --json");
  return ana;
}

#ifdef DEPLOYSIM_HAVE_CROSSCHECK
CLI::App* AddCrosscheckCommand(CLI::App& app, CommandLine& cl) {
  CLI::App* cc = app.add_subcommand(
      "crosscheck", "compare the reduced model with a Simbody multibody model (table + HDF5)");
  AddProfileArgument(cc, cl.profile_path);
  cc->add_option("-o,--output", cl.out_path,
                 "output HDF5 file (default: <profile stem>_crosscheck.h5 in the current folder)");
  cc->add_option("--accuracy", cl.cc_accuracy,
                 "Simbody Runge-Kutta-Merson accuracy (default 1e-12)")
      ->check(Number("in [1e-16, 0.1]", [](double v) { return v >= 1e-16 && v <= 0.1; }));
  cc->add_option("--until", cl.cc_until,
                 "stop at this time [s] (inside a hold stage or on a stage end)")
      ->check(Number("(finite)", [](double) { return true; }));
  cc->add_option("--dt", cl.ov.dt, "output sampling interval [s]")
      ->check(Number("> 0", [](double v) { return v > 0.0; }));
  cc->add_option("--tolerance", cl.cc_tolerance,
                 "largest relative difference that counts as agreement (default 1e-4): exit "
                 "status 4 beyond it, or when the flips or hinge events differ")
      ->check(Number("in (0, 1]", [](double v) { return v > 0.0 && v <= 1.0; }));
  cc->add_flag("--speed-study", cl.speed_study,
               "also run the deployment-speed study: quasi-rigid coupling vs Simbody for "
               "deployments of 1 to 1000 s (geometry-mode profiles)");
  cc->add_option("--csv", cl.speed_csv,
                 "speed-study CSV (default: <profile stem>_speed_study.csv)");
  cc->add_option("--own-error", cl.cc_own_error,
                 "hinge profiles: also run Simbody at this looser accuracy and print its "
                 "difference from the main run beside every figure (Simbody's own error)")
      ->check(Number("in [1e-16, 0.1]", [](double v) { return v >= 1e-16 && v <= 0.1; }));
  cc->footer(
      "Examples:\n"
      "  deploysim crosscheck deployment_profiles/smallsat_three_stage.yaml -o smallsat_cc.h5\n"
      "  deploysim crosscheck deployment_profiles/smallsat_spring_deploy.yaml --accuracy 1e-14 "
      "--own-error 1e-12 --until 300\n"
      "  deploysim crosscheck deployment_profiles/wing_nut.yaml --accuracy 1e-14\n"
      "  deploysim crosscheck deployment_profiles/smallsat_three_stage.yaml --until 300 "
      "--speed-study --csv speed.csv\n"
      "  /usr/bin/python3 tools/plot_speed_study.py speed.csv -o speed.png");
  return cc;
}
#endif

#ifdef DEPLOYSIM_HAVE_SWEEP
CLI::App* AddSweepCommand(CLI::App& app, CommandLine& cl) {
  CLI::App* swp = app.add_subcommand(
      "sweep",
      "run a parameter sweep (grid and/or Monte Carlo) and write one results table (HDF5)");
  swp->add_option("sweep", cl.sweep_path, "sweep file (YAML, docs/sweeps.md)")->required();
  swp->add_option("-o,--output", cl.out_path, "results HDF5 file")->required();
  swp->add_option("--threads", cl.sweep_threads,
                  "worker threads (default: all hardware threads; per rank under mpirun)")
      ->check(Number(
          "in [0, " + std::to_string(deploysim::sweep::kMaxThreads) + "]",
          [](double v) { return v >= 0 && v <= deploysim::sweep::kMaxThreads; }, true));
  swp->add_flag("--resume", cl.resume,
                "finish an interrupted sweep from its journal <output>.partial");
  swp->add_flag("--csv", cl.csv, "also write <output>.csv");
  swp->add_flag("-q,--quiet", cl.quiet, "no progress and no summary");
  swp->footer(
      "Examples:\n"
      "  deploysim sweep sweeps/smallsat_duration_spin.yaml -o smallsat_map.h5\n"
      "  deploysim sweep sweeps/smallsat_duration_spin.yaml -o smallsat_map.h5 --resume\n"
      "  mpirun -np 4 deploysim sweep sweeps/smallsat_duration_spin.yaml -o smallsat_map.h5\n"
      "  /usr/bin/python3 tools/plot_stability_map.py smallsat_map.h5 -o smallsat_map.png\n"
      "Ctrl-C stops after the cases at hand (exit 130); --resume finishes the sweep.\n"
      "Sweep files and results: docs/sweeps.md");
  return swp;
}
#endif

// Python tools (python_tool.h): their arguments, --help included, go to the script.
void AddPythonToolCommands(CLI::App& app, Subcommands& cmds) {
  cmds.rep = app.add_subcommand(
      "report",
      "a self-contained HTML mission report for a design review (deploysim report PROFILE -o "
      "REPORT.html; runs tools/report.py, see deploysim report --help)");
  cmds.view = app.add_subcommand(
      "view",
      "a self-contained 3D viewer page of a trajectory (deploysim view RESULT.h5 -o "
      "RESULT.html; runs tools/view.py, see deploysim view --help)");
  for (CLI::App* tool : {cmds.rep, cmds.view}) {
    tool->prefix_command();
    tool->set_help_flag();
  }
}

// Registers every subcommand, in the order --help lists them.
Subcommands AddSubcommands(CLI::App& app, CommandLine& cl) {
  Subcommands cmds;
  cmds.sim = AddSimulateCommand(app, cl);
  cmds.ana = AddAnalyzeCommand(app, cl);
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
  cmds.cc = AddCrosscheckCommand(app, cl);
#endif
#ifdef DEPLOYSIM_HAVE_SWEEP
  cmds.swp = AddSweepCommand(app, cl);
#endif
  cmds.meth = app.add_subcommand("methods", "list the integrators");
  AddPythonToolCommands(app, cmds);
  return cmds;
}

// Replaces this process with the Python tool the command line named. Returns false when
// it named none; true when the named one could not be started (the error is printed).
bool ExecNamedPythonTool(const Subcommands& cmds) {
  for (const auto& [tool, script] :
       {std::pair{cmds.rep, "report.py"}, std::pair{cmds.view, "view.py"}}) {
    if (!tool->parsed()) continue;
    std::string error;
    deploysim::cli::ExecPythonTool(script, tool->remaining(), error);
    std::cerr << "deploysim: error: " << error << "\n";
    return true;
  }
  return false;
}

// `deploysim methods`: every integrator with its summary, order and reference.
int ListMethods() {
  for (const std::string& name : deploysim::analysis::StepperNames()) {
    const auto s = deploysim::analysis::MakeStepper(name);
    std::cout << fmt::format("{:<13} {}\n{:<13} order {}{}; {}\n", name, s->info().summary, "",
                             s->info().order, s->info().adaptive ? ", adaptive" : ", fixed step",
                             s->info().reference);
  }
  return 0;
}

#ifdef DEPLOYSIM_HAVE_SWEEP
// `deploysim sweep`: runs the sweep file into one results table; kExitInterrupted when
// Ctrl-C stopped it (the journal then lets --resume finish it).
int RunSweepCommand(const CommandLine& cl, const deploysim::sweep::MpiSession& mpi) {
  const deploysim::sweep::SweepSpec spec = deploysim::sweep::LoadSweep(cl.sweep_path);
  const std::vector<std::string> inputs{cl.sweep_path, spec.base.source, spec.base.model.source};
  RefuseOutputOver(cl.out_path, inputs);
  if (cl.csv) RefuseOutputOver(cl.out_path + ".csv", inputs);
  deploysim::sweep::RunOptions o;
  o.output = cl.out_path;
  o.csv = cl.csv;
  o.resume = cl.resume;
  o.threads = cl.sweep_threads;
  o.progress = cl.quiet ? nullptr : &std::cerr;
  o.progress_tty = isatty(fileno(stderr)) != 0;
  o.cancel = &deploysim::sweep::InstallInterruptHandlers();
  o.mpi = &mpi;
  const deploysim::sweep::RunSummary s = deploysim::sweep::RunSweep(spec, o);
  if (!s.complete) {
    if (mpi.rank() == 0) {
      std::cerr << "deploysim: interrupted: " << deploysim::sweep::FormatSummary(s, o) << "\n";
    }
    return kExitInterrupted;
  }
  if (!cl.quiet && mpi.rank() == 0) std::cout << deploysim::sweep::FormatSummary(s, o) << "\n";
  return 0;
}
#endif

// `deploysim simulate`: runs the profile into its trajectory file(s), then prints the
// summary, the deployment timeline and, on request, the coupling comparison.
int RunSimulate(CommandLine& cl, const deploysim::run::CompiledRun& run, bool comparable) {
  const deploysim::schedule::Profile& profile = run.profile();
  if (cl.out_path.empty()) {
    cl.out_path = std::filesystem::path(cl.profile_path).stem().string() + ".h5";
  }
  const std::vector<std::string> inputs{cl.profile_path, profile.model.source};
  RefuseOutputOver(cl.out_path, inputs);
  if (cl.csv) RefuseOutputOver(cl.out_path + ".csv", inputs);
  // Streamed to both temporaries as it runs; both complete before either is renamed
  // (io::TrajectoryOutputs). SIGINT/SIGTERM/SIGHUP remove named temporaries.
  deploysim::io::RemoveTemporariesOnSignals();
  deploysim::io::TrajectoryOutputs outputs(cl.out_path, cl.csv ? cl.out_path + ".csv" : "",
                                           profile);
  const MissionResult r =
      NamingFile(cl.profile_path,
                 [&] { return deploysim::run::RunMission(run, outputs, Progress(cl.quiet, run)); },
                 {cl.out_path, cl.out_path + ".csv"});
  if (r.termination != deploysim::integrators::Termination::kReachedEnd) {
    std::cerr << "deploysim: error: " << cl.profile_path << ": integration " << r.message << "\n";
    return kExitIncomplete;
  }
  outputs.Finish(r);
  outputs.Commit();
  if (cl.quiet) return 0;
  std::cout << deploysim::cli::FormatSummary(r);
  const std::string timeline = deploysim::cli::FormatTimeline(r);
  if (!timeline.empty()) std::cout << "\n" << timeline;
  if (cl.compare && profile.is_hinge_profile()) {
    std::cout << "\n--compare-coupling: not applicable to a hinge profile (free hinges "
                 "are coupled exactly)\n";
  }
  if (cl.compare && comparable) {
    std::cout << "\n"
              << deploysim::cli::FormatCouplingComparison(NamingFile(
                     cl.profile_path, [&] { return deploysim::run::CompareCouplings(profile); }));
  }
  std::cout << "\nwrote " << cl.out_path << (cl.csv ? " and " + cl.out_path + ".csv" : "") << "\n";
  return 0;
}

#ifdef DEPLOYSIM_HAVE_CROSSCHECK
// `deploysim crosscheck`: the reduced model against Simbody (the free-hinge model for a
// hinge profile), then on request the deployment-speed study.
int RunCrosscheck(CommandLine& cl, const deploysim::schedule::Profile& profile, bool geometry) {
  namespace xc = deploysim::crosscheck;
  if (cl.speed_study && (!geometry || profile.is_hinge_profile())) {
    throw std::invalid_argument(cl.profile_path +
                                ": --speed-study needs a geometry-mode stage profile");
  }
  if (cl.cc_own_error > 0.0 && !profile.is_hinge_profile()) {
    throw std::invalid_argument(cl.profile_path + ": --own-error is for hinge profiles");
  }
  const std::string stem = std::filesystem::path(cl.profile_path).stem().string();
  if (cl.out_path.empty()) cl.out_path = stem + "_crosscheck.h5";
  RefuseOutputOver(cl.out_path, {cl.profile_path, profile.model.source});
  if (profile.is_hinge_profile()) {
    // Free, prescribed and locked hinges: the independent Simbody model of free hinges.
    xc::FreeHingeCrosscheckOptions o;
    o.accuracy = cl.cc_accuracy;
    o.own_error_accuracy = cl.cc_own_error;
    o.t_end = cl.cc_until;
    const xc::FreeHingeCrosscheckResult r =
        NamingFile(cl.profile_path, [&] { return xc::RunFreeHingeCrosscheck(profile, o); });
    xc::WriteCrosscheckFile(cl.out_path, xc::AsCrosscheckResult(r));
    const xc::CrosscheckVerdict v =
        xc::Judge(r.difference, r.max_flip_difference, r.events.same_sequence, r.events.max_time,
                  r.profile.t_end() - r.profile.t_begin(), cl.cc_tolerance);
    std::cout << xc::FormatFreeHingeCrosscheckTable(r) << "\n"
              << xc::FormatVerdict(v) << "\nwrote " << cl.out_path << "\n";
    return v.agree ? 0 : kExitDisagree;
  }
  xc::CrosscheckOptions o;
  o.accuracy = cl.cc_accuracy;
  o.t_end = cl.cc_until;
  const xc::CrosscheckResult r =
      NamingFile(cl.profile_path, [&] { return xc::RunCrosscheck(profile, o); });
  xc::WriteCrosscheckFile(cl.out_path, r);
  const xc::CrosscheckVerdict v =
      xc::Judge(r.difference, r.max_flip_difference, true, 0.0,
                r.profile.t_end() - r.profile.t_begin(), cl.cc_tolerance);
  std::cout << xc::FormatCrosscheckTable(r) << "\n"
            << xc::FormatVerdict(v) << "\nwrote " << cl.out_path << "\n";
  if (cl.speed_study) {
    xc::SpeedStudyOptions so;
    so.accuracy = cl.cc_accuracy;
    const xc::SpeedStudyResult st = xc::SpeedStudy(profile, so);
    if (cl.speed_csv.empty()) cl.speed_csv = stem + "_speed_study.csv";
    xc::WriteSpeedStudyCsv(cl.speed_csv, st);
    std::cout << "\n"
              << xc::FormatSpeedStudyTable(st) << "\nwrote " << cl.speed_csv
              << " (plot: /usr/bin/python3 tools/plot_speed_study.py " << cl.speed_csv << ")\n";
  }
  return v.agree ? 0 : kExitDisagree;
}
#endif

// `deploysim analyze`: the summary and timeline tables (or JSON), with the coupling
// comparison where it applies.
int RunAnalyze(const CommandLine& cl, const deploysim::run::CompiledRun& run, bool comparable) {
  const deploysim::schedule::Profile& profile = run.profile();
  // The table needs no trajectory: its samples are dropped as they come (bounded memory).
  deploysim::run::NullSink discard;
  const MissionResult r = NamingFile(cl.profile_path, [&] {
    return deploysim::run::RunMission(run, discard, Progress(false, run));
  });
  std::optional<deploysim::run::CouplingComparison> c;
  if (comparable) {
    c = NamingFile(cl.profile_path, [&] { return deploysim::run::CompareCouplings(profile); });
  }
  if (cl.json) {
    std::cout << deploysim::cli::FormatJson(r, c ? &*c : nullptr);
  } else {
    std::cout << deploysim::cli::FormatSummary(r);
    const std::string timeline = deploysim::cli::FormatTimeline(r);
    if (!timeline.empty()) std::cout << "\n" << timeline;
    if (c) std::cout << "\n" << deploysim::cli::FormatCouplingComparison(*c);
  }
  return 0;
}

}  // namespace

// The subcommand nearest a mistyped one (edit distance at most 3), or "".
std::string NearestCommand(const CLI::App& app, const std::string& typed) {
  std::string best;
  std::size_t best_d = 4;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    const std::string& name = sub->get_name();
    // Levenshtein distance, one row at a time.
    std::vector<std::size_t> row(name.size() + 1);
    for (std::size_t j = 0; j <= name.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= typed.size(); ++i) {
      std::size_t diag = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= name.size(); ++j) {
        const std::size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (typed[i - 1] != name[j - 1])});
        diag = up;
      }
    }
    if (row[name.size()] < best_d) {
      best_d = row[name.size()];
      best = name;
    }
  }
  return best;
}

// A first argument that is no option and no subcommand: "unknown command", with the
// nearest one. Returns true when it printed that error.
bool RefuseUnknownCommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return false;
  const std::string typed = argv[1];
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == typed) return false;
  }
  const std::string near = NearestCommand(app, typed);
  std::cerr << "deploysim: error: unknown command '" << typed.substr(0, 40) << "'"
            << (near.empty() ? std::string() : " (did you mean '" + near + "'?)")
            << " (see deploysim --help)\n";
  return true;
}

namespace deploysim::cli {

int Main(int argc, char** argv) {
  // A file size limit (ulimit -f) then fails a write with EFBIG, reported by name.
  std::signal(SIGXFSZ, SIG_IGN);
#ifdef DEPLOYSIM_HAVE_SWEEP
  // First: under mpirun, MPI_Init may consume arguments. A no-op otherwise.
  deploysim::sweep::MpiSession mpi(&argc, &argv);
#endif
  CLI::App app{
      "deploysim: does a spinning spacecraft stay put when it deploys its panels, or "
      "does it start to tumble? (Dzhanibekov effect with time-varying inertia)"};
  ConfigureApp(app);
  CommandLine cl;
  const Subcommands cmds = AddSubcommands(app, cl);

  if (RefuseUnknownCommand(app, argc, argv)) return kExitBadInput;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad option or value is bad input like any other
    // (exit 1), not one of CLI11's own exit codes.
    return app.exit(e) == 0 ? 0 : kExitBadInput;
  }

  if (ExecNamedPythonTool(cmds)) return kExitBadInput;

  try {
    if (cmds.meth->parsed()) return ListMethods();
#ifdef DEPLOYSIM_HAVE_SWEEP
    if (cmds.swp->parsed()) return RunSweepCommand(cl, mpi);
#endif
    const std::shared_ptr<const deploysim::run::CompiledRun> run = Load(cl.profile_path, cl.ov);
    const deploysim::schedule::Profile& profile = run->profile();
    const bool geometry = profile.mode == deploysim::schedule::Mode::kGeometry;
    // The exact vs quasi-rigid comparison concerns prescribed stages; free hinges are
    // always coupled exactly.
    const bool comparable = geometry && !profile.is_hinge_profile();
    if (cmds.sim->parsed()) return RunSimulate(cl, *run, comparable);
#ifdef DEPLOYSIM_HAVE_CROSSCHECK
    if (cmds.cc->parsed()) return RunCrosscheck(cl, profile, geometry);
#endif
    if (cmds.ana->parsed()) return RunAnalyze(cl, *run, comparable);
  } catch (const std::exception& e) {
    std::cerr << "deploysim: error: " << e.what() << "\n";
#ifdef DEPLOYSIM_HAVE_SWEEP
    // Under mpirun the other ranks would wait for this one forever: end the job.
    std::cerr.flush();
    mpi.AbortIfParallel(kExitBadInput);
#endif
    return kExitBadInput;
  }
  return 0;
}

}  // namespace deploysim::cli
