#include "cli/batch.h"

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>
#include <thread>

#include "cli/atlas.h"
#include "cli/batch_child.h"
#include "cli/batch_inputs.h"
#include "cli/batch_report.h"
#include "cli/methods.h"
#include "cli/progress_line.h"

namespace harmonia::cli {

namespace fs = std::filesystem;

namespace {

constexpr int kMostJobs = 1024;
constexpr const char* kLogName = "batch-log.jsonl";
// This very program, started again for each input (Linux: the running executable itself, even
// when its file has since been replaced).
constexpr const char* kThisProgram = "/proc/self/exe";
// How long the batch waits for its children's output before it looks at Ctrl-C again.
constexpr std::chrono::milliseconds kWaitSlice{250};

// The planar methods of `harmonia unwrap`, in its spelling.
std::vector<std::string> unwrap_method_names() {
  std::vector<std::string> names;
  for (const MethodKind method : {MethodKind::conformal, MethodKind::lscm, MethodKind::qhm,
                                  MethodKind::abf, MethodKind::linabf, MethodKind::free})
    names.emplace_back(to_string(method));
  return names;
}

int core_count() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

}  // namespace

CLI::App* add_batch_command(CLI::App& app, BatchOptions& options) {
  CLI::App* command = app.add_subcommand(
      "batch",
      "Texture atlas (or a planar map) of many meshes, N child processes at a time; memory stays "
      "bounded: at most N children, each holding one mesh");
  command
      ->add_option("INPUTS", options.inputs,
                   "Mesh files and folders (searched recursively for .obj, .off, .ply, .stl, .gltf, .glb)");
  command
      ->add_option("--out", options.out,
                   "Output folder: OUT/<path relative to its given folder>.obj per input (.glb or "
                   ".gltf for a glTF input: its document with the atlas added), and "
                   "the log OUT/batch-log.jsonl (created if missing)")
      ->required();
  command
      ->add_option("-j,--jobs", options.jobs,
                   "Inputs run at a time, each in its own process holding one mesh (default: one "
                   "per core); with one job the child flattens on every core")
      ->check(CLI::Range(1, kMostJobs));
  CLI::Option* atlas =
      command->add_flag("--atlas", options.atlas, "Run `harmonia atlas` on each input (default)");
  command
      ->add_option("--method", options.method,
                   "Run `harmonia unwrap --method M` on each input instead (a disk, or any mesh "
                   "with --cut)")
      ->check(CLI::IsMember(unwrap_method_names()))
      ->excludes(atlas);
  add_atlas_layout_options(*command, options.resolution, options.padding, options.max_distortion);
  command
      ->add_option("--cleanup", options.cleanup,
                   "Passed on: none (atlas only), strict or repair (see `atlas --help`, "
                   "`unwrap --help`)")
      ->check(CLI::IsMember({"none", "strict", "repair"}));
  command->add_flag("--cut", options.cut, "--method only: cut inputs that are not disks open");
  command->add_flag("--keep-splits", options.keep_splits,
                    "Atlas only: the file's splits are chart boundaries (see `atlas --help`)");
  command->add_flag("--repack", options.repack,
                    "Atlas only: keep each input's own UV charts and only pack them (see `atlas --help`)");
  command
      ->add_option("--texels-per-unit", options.texels_per_unit,
                   "Atlas only: every atlas at this texel density, on as many pages as it needs "
                   "(see `atlas --help`)")
      ->check(CLI::PositiveNumber);
  command
      ->add_option("--max-pages", options.max_pages,
                   "Atlas only, with --texels-per-unit: the most pages an atlas may have")
      ->check(CLI::NonNegativeNumber);
  command->add_flag("--join-charts", options.join_charts,
                    "Atlas only: join charts whose union flattens within the limit (see `atlas --help`)");
  command->add_flag("--resume", options.resume,
                    "Skip the inputs whose output exists (outputs are written atomically, so an "
                    "existing one is complete), except those the log says were written with "
                    "defects (exit code 3): they run again; append to the log");
  command
      ->add_flag("--resume-keep-defective", options.resume_keep_defective,
                 "With --resume: skip the outputs written with defects too")
      ->needs("--resume");
  command->add_flag("--json", options.json, "Print the summary as one JSON object");
  command
      ->add_option("--backend", options.backend, "Passed on: cpu, vulkan or auto (see `atlas --help`)")
      ->check(CLI::IsMember({"auto", "cpu", "vulkan"}));
  // For another scheduler running the batch (python -m harmonia.distributed; docs/python.md).
  command->add_flag("--plan", options.plan,
                    "Print the inputs' outputs and what --resume skips (JSON lines), run nothing");
  command
      ->add_option("--task", options.task,
                   "Run one input to its planned output as the batch does and print its log line")
      ->expected(2)
      ->excludes("--plan");
  command
      ->add_option("--summary-of", options.summary_of,
                   "Print the summary of a run's log lines (a file) instead of running anything")
      ->excludes("--plan", "--task");
  command->add_option("--elapsed", options.elapsed, "With --summary-of: the run's wall-clock seconds")
      ->needs("--summary-of")
      ->check(CLI::NonNegativeNumber);
  return command;
}

namespace {

// Refuses options that mean nothing for the chosen command, before any work.
void check_options(const BatchOptions& options) {
  if (options.method) {
    if (options.resolution || options.padding || options.max_distortion) {
      throw CliFailure(ExitCode::usage,
                       "--resolution, --padding and --max-distortion apply to --atlas only");
    }
    if (options.cleanup == "none") {
      throw CliFailure(ExitCode::usage,
                       "--cleanup none applies to --atlas only (`unwrap` takes "
                       "strict or repair)");
    }
    if (options.keep_splits) throw CliFailure(ExitCode::usage, "--keep-splits applies to --atlas only");
    if (options.join_charts) throw CliFailure(ExitCode::usage, "--join-charts applies to --atlas only");
    if (options.repack) throw CliFailure(ExitCode::usage, "--repack applies to --atlas only");
    if (options.texels_per_unit || options.max_pages)
      throw CliFailure(ExitCode::usage, "--texels-per-unit and --max-pages apply to --atlas only");
  } else if (options.cut) {
    throw CliFailure(ExitCode::usage, "--cut applies to --method only (an atlas cuts any mesh)");
  }
}

// The command line of the child that makes `input`'s output: this program's `atlas` or
// `unwrap`, with its report as JSON on its standard output and nothing but its failure line on
// its standard error.
std::vector<std::string> child_arguments(const BatchOptions& options, const BatchInput& input,
                                         int threads_per_child) {
  std::vector<std::string> arguments = {"harmonia"};
  if (options.method) {
    arguments.insert(arguments.end(), {"unwrap", "--method", *options.method});
    if (options.cut) arguments.emplace_back("--cut");
  } else {
    arguments.insert(arguments.end(), {"atlas", "--threads", std::to_string(threads_per_child)});
    if (options.resolution) {
      arguments.insert(arguments.end(), {"--resolution", options.resolution->text()});
    }
    if (options.padding) {
      arguments.insert(arguments.end(), {"--padding", std::to_string(*options.padding)});
    }
    if (options.max_distortion) {
      arguments.insert(arguments.end(),
                       {"--max-distortion", nlohmann::json(*options.max_distortion).dump()});
    }
    if (options.texels_per_unit) {
      arguments.insert(arguments.end(), {"--texels-per-unit", nlohmann::json(*options.texels_per_unit).dump()});
    }
    if (options.max_pages) arguments.insert(arguments.end(), {"--max-pages", std::to_string(*options.max_pages)});
    if (options.keep_splits) arguments.emplace_back("--keep-splits");
    if (options.join_charts) arguments.emplace_back("--join-charts");
    if (options.repack) arguments.emplace_back("--repack");
  }
  if (options.cleanup) arguments.insert(arguments.end(), {"--cleanup", *options.cleanup});
  if (options.backend) arguments.insert(arguments.end(), {"--backend", *options.backend});
  // "--" ends the options: a file whose name starts with '-' is still a file.
  arguments.insert(arguments.end(),
                   {"--json", "--quiet", "--", input.input.string(), input.output.string()});
  return arguments;
}

// The reason a failed child gave: its last line "harmonia: <reason>" (every failure of the
// program ends with one), or else its last line of any kind.
std::string failure_reason(const std::string& standard_error) {
  constexpr std::string_view kPrefix = "harmonia: ";
  std::string last_reason;
  std::string last_line;
  std::istringstream lines(standard_error);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    last_line = line;
    if (line.rfind(kPrefix, 0) == 0) last_reason = line.substr(kPrefix.size());
  }
  return last_reason.empty() ? last_line : last_reason;
}

// The few figures of a result that the log keeps: for an atlas the ones that say whether it is
// usable, for a planar map its metrics. Null when the report has none.
nlohmann::json quality_of(const nlohmann::json& report, bool atlas) {
  if (!report.is_object()) return nullptr;
  if (!atlas) return report.contains("metrics") ? report["metrics"] : nlohmann::json(nullptr);
  if (report.value("status", "") != "ok") return nullptr;
  return {
      {"charts", report.value("charts", 0)},
      {"coverage", report.value("coverage", 0.0)},
      {"l2_stretch", report.value("l2_stretch", 0.0)},
      {"flips", report.value("flipped_triangles", 0)},
      {"overlaps", report.value("overlapping_texels", 0)},
  };
}

BatchRecord record_of(const BatchInput& input) {
  BatchRecord record;
  record.input = input.input.string();
  record.output = input.output.string();
  return record;
}

// An input that failed before a child ran for it, with the exit code its child would have had.
BatchRecord failed_record(const BatchInput& input, ExitCode code, const std::string& error) {
  BatchRecord record = record_of(input);
  record.status = BatchStatus::failed;
  record.error = error;
  record.exit_code = static_cast<int>(code);
  return record;
}

BatchRecord child_record(const BatchInput& input, const FinishedChild& child, bool atlas) {
  BatchRecord record = record_of(input);
  record.seconds = child.seconds;
  record.child_ran = true;
  record.exit_code = child.exit_code;
  const nlohmann::json report =
      nlohmann::json::parse(child.standard_output, nullptr, /*allow_exceptions=*/false);
  record.quality = quality_of(report, atlas);
  if (child.signal != 0) {
    record.status = BatchStatus::failed;
    record.signal = signal_name(child.signal);
    record.error = "killed by signal " + signal_description(child.signal);
  } else if (child.exit_code != 0) {
    record.status = BatchStatus::failed;
    record.error = failure_reason(child.standard_error);
    if (record.error.empty()) record.error = "exit code " + std::to_string(child.exit_code);
  } else if (report.is_discarded()) {
    record.status = BatchStatus::failed;
    record.error = "the child's report is not JSON";
  }
  return record;
}

// How the children share the machine.
struct ChildPlan {
  int workers = 1;                       // Children at a time.
  int threads_per_child = 1;             // The atlas' --threads.
  std::vector<std::string> environment;  // NAME=value set in every child.
};

// -j N uses N cores: N children at a time, each flattening on one thread, with OpenBLAS and
// OpenMP (CHOLMOD) held to one thread too, since each would otherwise start a pool as large as the
// machine in every child and the pools would fight over the cores. So -j 1 runs one job at a time
// on one core, as make -j1 does, and -j N is the batch's parallelism (a single mesh that should use
// every core is `harmonia atlas`'s job, whose --threads defaults to the cores).
ChildPlan plan_children(int jobs, std::size_t inputs_to_run) {
  ChildPlan plan;
  plan.workers = std::max(1, std::min(jobs, static_cast<int>(inputs_to_run)));
  plan.threads_per_child = 1;
  plan.environment = {"OPENBLAS_NUM_THREADS=1", "OMP_NUM_THREADS=1"};
  return plan;
}

// Runs the inputs `to_run` (indices into `inputs`), plan.workers at a time, and hands each
// outcome to `finish` as it comes. On Ctrl-C (SIGINT or SIGTERM) the children are stopped (their
// own handlers remove their unfinished outputs) and the process ends as the signal would have
// ended it; the inputs that were running get no record, so that --resume runs them again.
template <typename Finish>
void run_children(const BatchOptions& options, const std::vector<BatchInput>& inputs,
                  const std::vector<std::size_t>& to_run, const ChildPlan& plan, BatchTally& tally,
                  ProgressLine& progress, Finish finish) {
  std::string shown_progress;
  const auto show_progress = [&](std::size_t running) {
    const std::string text = tally.progress_text(running);
    if (text != shown_progress) progress.show(text);
    shown_progress = text;
  };
  InterruptWatch interrupt;
  ChildPool pool(kThisProgram);
  std::size_t next = 0;
  show_progress(0);
  while (next < to_run.size() || pool.running() > 0) {
    if (interrupt.received() != 0) {
      pool.terminate_all();
      progress.clear();
      interrupt.end_as_interrupted();
    }
    while (next < to_run.size() && pool.running() < static_cast<std::size_t>(plan.workers)) {
      const BatchInput& input = inputs[to_run[next]];
      // A folder that cannot be made leaves the child an output it cannot write: it says so.
      std::error_code ignored;
      fs::create_directories(input.output.parent_path(), ignored);
      try {
        pool.start(static_cast<int>(to_run[next]),
                   child_arguments(options, input, plan.threads_per_child), plan.environment);
      } catch (const std::system_error& failure) {
        finish(failed_record(input, ExitCode::environment,
                             std::string("cannot start its process: ") + failure.what()));
      }
      ++next;
    }
    for (const FinishedChild& child : pool.wait(kWaitSlice))
      finish(child_record(inputs[static_cast<std::size_t>(child.tag)], child, !options.method));
    show_progress(pool.running());
  }
}

// --task INPUT OUTPUT: the one input run as run_children runs it, its log line printed.
ExitCode run_one_task(const BatchOptions& options) {
  const BatchInput input{fs::path(options.task.at(0)), fs::path(options.task.at(1))};
  const ChildPlan plan = plan_children(1, 1);
  BatchRecord record;
  std::error_code ignored;
  fs::create_directories(input.output.parent_path(), ignored);
  InterruptWatch interrupt;
  ChildPool pool(kThisProgram);
  // The process that asked for the task (a worker of another scheduler): when it is gone (killed,
  // out of memory), nobody waits for the result and the input is run again elsewhere, so the
  // child is stopped (it removes its unfinished output).
  const pid_t asked_by = ::getppid();
  try {
    pool.start(0, child_arguments(options, input, plan.threads_per_child), plan.environment);
    for (bool finished = false; !finished;) {
      if (interrupt.received() != 0) {
        pool.terminate_all();
        interrupt.end_as_interrupted();
      }
      if (::getppid() != asked_by) {
        pool.terminate_all();
        return ExitCode::environment;
      }
      for (const FinishedChild& child : pool.wait(kWaitSlice)) {
        record = child_record(input, child, !options.method);
        finished = true;
      }
    }
  } catch (const std::system_error& failure) {
    record = failed_record(input, ExitCode::environment, std::string("cannot start its process: ") + failure.what());
  }
  std::cout << log_line(record).dump() << '\n';
  return ExitCode::ok;
}

// --summary-of LINES: the summary of a run's records as run_batch prints it at its end.
ExitCode summarize_records(const BatchOptions& options) {
  std::ifstream lines(*options.summary_of);
  if (!lines) throw CliFailure(ExitCode::input, *options.summary_of + ": cannot read the records");
  std::vector<BatchRecord> records;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty()) continue;
    const nlohmann::json entry = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (entry.is_discarded()) {
      throw CliFailure(ExitCode::input, *options.summary_of + ":" + std::to_string(records.size() + 1) +
                                            ": not a log line");
    }
    records.push_back(record_from_log_line(entry));
  }
  const int jobs = options.jobs > 0 ? options.jobs : core_count();
  BatchTally tally(records.size(), jobs);
  for (const BatchRecord& record : records) tally.add(record);
  tally.set_elapsed_seconds(options.elapsed);
  const fs::path log = fs::path(options.out) / kLogName;
  if (options.json) {
    nlohmann::json summary = tally.summary_json(log);
    summary["command"] = options.method ? "unwrap --method " + *options.method : "atlas";
    summary["out"] = options.out;
    std::cout << summary.dump(2) << '\n';
  } else {
    tally.print_summary(std::cout, log);
  }
  if (!tally.all_succeeded()) throw CliFailure(ExitCode::input, "some inputs failed; " + log.string() + " says why");
  return ExitCode::ok;
}

}  // namespace

ExitCode run_batch(const BatchOptions& options, const GlobalOptions& global) {
  check_options(options);
  if (!options.task.empty()) return run_one_task(options);
  if (options.summary_of) return summarize_records(options);
  if (options.inputs.empty()) throw CliFailure(ExitCode::usage, "INPUTS is required");
  const fs::path out_dir(options.out);
  const std::vector<BatchInput> inputs = find_batch_inputs(options.inputs, out_dir);
  if (inputs.empty()) {
    throw CliFailure(ExitCode::input, "no mesh file (.obj, .off, .ply, .stl, .gltf, .glb) in the inputs given");
  }
  std::error_code error;
  fs::create_directories(out_dir, error);
  if (error || !fs::is_directory(out_dir, error)) {
    throw CliFailure(ExitCode::environment, out_dir.string() + ": cannot make the output folder (" +
                                                error.message() + ")");
  }
  // The plan writes no log: the scheduler that runs it does, from the lines printed.
  std::optional<BatchLog> log;
  if (!options.plan) log.emplace(out_dir / kLogName, options.resume);  // read (for --resume) before appended to
  const int jobs = options.jobs > 0 ? options.jobs : core_count();
  BatchTally tally(inputs.size(), jobs);
  const auto finish = [&](const BatchRecord& record) {
    if (options.plan) {
      std::cout << nlohmann::json{{"input", record.input}, {"output", record.output}, {"run", false},
                                  {"record", log_line(record)}}.dump()
                << '\n';
      return;
    }
    log->write(record);
    tally.add(record);
  };

  // With --resume, what need not run is settled first: the outputs already there (written
  // atomically, so an existing one is complete), but for those whose last log line says they
  // were written with defects.
  const std::set<std::string> defective =
      options.resume && !options.resume_keep_defective ? outputs_written_with_defects(out_dir / kLogName)
                                                       : std::set<std::string>{};
  std::vector<std::size_t> to_run;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    if (options.resume && fs::exists(inputs[i].output, error) &&
        !defective.contains(inputs[i].output.string())) {
      BatchRecord skipped = record_of(inputs[i]);
      skipped.status = BatchStatus::skipped;
      finish(skipped);
    } else {
      to_run.push_back(i);
    }
  }

  // Largest files first: the long jobs start early and the short ones fill in around them, so
  // that the workers finish together (longest-processing-time-first scheduling). Ties keep the
  // input order; the log's lines come in the order the inputs finish either way.
  std::vector<std::uintmax_t> sizes(inputs.size(), 0);
  for (const std::size_t i : to_run) sizes[i] = fs::file_size(inputs[i].input, error);
  std::stable_sort(to_run.begin(), to_run.end(),
                   [&sizes](std::size_t a, std::size_t b) { return sizes[a] > sizes[b]; });

  if (options.plan) {
    for (const std::size_t i : to_run)
      std::cout << nlohmann::json{{"input", inputs[i].input.string()}, {"output", inputs[i].output.string()},
                                  {"run", true}}.dump()
                << '\n';
    return ExitCode::ok;
  }

  ProgressLine progress(global, options.json);
  run_children(options, inputs, to_run, plan_children(jobs, to_run.size()), tally, progress,
               finish);
  progress.clear();

  if (options.json) {
    nlohmann::json summary = tally.summary_json(log->path());
    summary["command"] = options.method ? "unwrap --method " + *options.method : "atlas";
    summary["out"] = out_dir.string();
    std::cout << summary.dump(2) << '\n';
  } else {
    tally.print_summary(std::cout, log->path());
  }
  if (!tally.all_succeeded()) {
    throw CliFailure(ExitCode::input, "some inputs failed; " + log->path().string() + " says why");
  }
  return ExitCode::ok;
}

}  // namespace harmonia::cli
