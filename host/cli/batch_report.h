#pragma once
//! \file batch_report.h
//! \brief What `harmonia batch` says about its inputs: one record per input (the JSON-lines log),
//! the progress bar, and the summary at the end (a table, or JSON).

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <ostream>
#include <set>
#include <string>
#include <vector>

namespace harmonia::cli {

enum class BatchStatus { ok, failed, skipped };
[[nodiscard]] const char* to_string(BatchStatus status);

//! The outcome of one input.
struct BatchRecord {
  std::string input;
  std::string output;
  BatchStatus status = BatchStatus::ok;
  std::string error;     //!< Why it failed (the child's failure line); empty otherwise.
  int exit_code = 0;     //!< The child's exit code (-1 when a signal ended it).
  std::string signal;    //!< "SIGSEGV" when a signal ended the child.
  double seconds = 0.0;  //!< Wall-clock seconds of its child.
  bool child_ran = false;  //!< Whether a child ran for it (not skipped, and it could start).
  //! Times it was started again after the process running it was lost (another scheduler's
  //! worker killed: python -m harmonia.distributed); `harmonia batch` never needs to.
  int retries = 0;
  //! The result's quality from the child's report (atlas: charts, coverage, l2_stretch, flips,
  //! overlaps; a planar map: its metrics); null when there is none.
  nlohmann::json quality;
};

//! The log line of a record: one JSON object on one line, the fields of BatchRecord (error and
//! signal null when there is none).
[[nodiscard]] nlohmann::json log_line(const BatchRecord& record);

//! The record a log line holds (child_ran: it was not skipped). Missing fields keep their
//! defaults.
[[nodiscard]] BatchRecord record_from_log_line(const nlohmann::json& line);

//! The batch's log file, `out_dir`/batch-log.jsonl: one line per input as it finishes, written
//! through at once so that an interrupted batch leaves the lines of what it finished.
class BatchLog {
 public:
  //! Appends to an existing log when `append` (a resumed batch), else starts a new one. Throws
  //! CliFailure(environment) naming the file when it cannot be opened.
  BatchLog(const std::filesystem::path& path, bool append);
  void write(const BatchRecord& record);
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  std::ofstream file_;
};

//! The outputs that the log at `path` says were written with defects: those whose last line of
//! a run (skipped lines aside) has exit code 3. Empty when there is no log; a line that is not a
//! log line (a log cut by a crash) is passed over.
[[nodiscard]] std::set<std::string> outputs_written_with_defects(const std::filesystem::path& path);

//! The counts of a batch as it runs, and what its progress bar and summary say.
class BatchTally {
 public:
  BatchTally(std::size_t inputs, int jobs);
  void add(const BatchRecord& record);
  [[nodiscard]] bool all_succeeded() const { return failed_ == 0; }
  //! The wall-clock seconds to report instead of the time since construction (a run that another
  //! scheduler made, summarized afterwards).
  void set_elapsed_seconds(double seconds) { elapsed_override_ = seconds; }

  //! "[#######.........] 7/16: 6 ok, 1 failed, 0 skipped; 2 running; ETA 12 s; slowest
  //! bunny.obj 4.1 s".
  [[nodiscard]] std::string progress_text(std::size_t running) const;

  //! The summary as rows of a table (inputs, ok, failed, skipped, jobs, seconds, mean seconds
  //! per file run, the slowest files, each failure, the log) on `out`.
  void print_summary(std::ostream& out, const std::filesystem::path& log) const;
  //! The same as one JSON object.
  [[nodiscard]] nlohmann::json summary_json(const std::filesystem::path& log) const;

 private:
  // What the summary needs of each input (not its quality: the log has that).
  struct Finished {
    std::string input;
    BatchStatus status = BatchStatus::ok;
    std::string error;
    double seconds = 0.0;
    bool child_ran = false;
  };

  [[nodiscard]] double elapsed_seconds() const;
  [[nodiscard]] double mean_seconds_per_file() const;
  //! The inputs that ran (not skipped), slowest first, at most `count`.
  [[nodiscard]] std::vector<const Finished*> slowest(std::size_t count) const;

  std::size_t inputs_ = 0;
  int jobs_ = 1;
  std::size_t ok_ = 0;
  std::size_t failed_ = 0;
  std::size_t skipped_ = 0;
  std::vector<Finished> finished_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::optional<double> elapsed_override_;
};

}  // namespace harmonia::cli
