#include "cli/batch_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "cli/common.h"
#include "cli/report_output.h"

namespace harmonia::cli {

namespace {

constexpr int kProgressBarWidth = 24;        // Characters of the bar between its brackets.
constexpr std::size_t kSlowestListed = 3;    // Slowest files named in the summary.
constexpr std::size_t kFailuresListed = 20;  // Failures named in the text summary (all in JSON).
constexpr long long kSecondsPerMinute = 60;
constexpr long long kSecondsPerHour = 3600;

// "4.2 s", "3 min 20 s", "2 h 5 min": a duration as people read it on a progress bar.
std::string duration_text(double seconds) {
  const long long whole = std::llround(seconds);
  if (whole < kSecondsPerMinute) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f s", seconds);
    return text;
  }
  if (whole < kSecondsPerHour) {
    return std::to_string(whole / kSecondsPerMinute) + " min " +
           std::to_string(whole % kSecondsPerMinute) + " s";
  }
  return std::to_string(whole / kSecondsPerHour) + " h " +
         std::to_string(whole % kSecondsPerHour / kSecondsPerMinute) + " min";
}

nlohmann::json null_if_empty(const std::string& text) {
  return text.empty() ? nlohmann::json(nullptr) : nlohmann::json(text);
}

}  // namespace

const char* to_string(BatchStatus status) {
  switch (status) {
    case BatchStatus::ok:
      return "ok";
    case BatchStatus::failed:
      return "failed";
    case BatchStatus::skipped:
      return "skipped";
  }
  return "failed";  // Unreachable: -Werror=switch keeps the list above complete.
}

nlohmann::json log_line(const BatchRecord& record) {
  return {
      {"input", record.input},
      {"output", record.output},
      {"status", to_string(record.status)},
      {"error", null_if_empty(record.error)},
      {"exit_code", record.exit_code},
      {"signal", null_if_empty(record.signal)},
      {"seconds", record.seconds},
      {"quality", record.quality},
      {"retries", record.retries},
  };
}

BatchRecord record_from_log_line(const nlohmann::json& line) {
  BatchRecord record;
  const auto text = [&line](const char* key) {
    return line.contains(key) && line[key].is_string() ? line[key].get<std::string>() : std::string();
  };
  record.input = text("input");
  record.output = text("output");
  const std::string status = text("status");
  record.status = status == "ok" ? BatchStatus::ok : status == "skipped" ? BatchStatus::skipped : BatchStatus::failed;
  record.error = text("error");
  record.signal = text("signal");
  record.exit_code = line.value("exit_code", 0);
  record.seconds = line.value("seconds", 0.0);
  record.retries = line.value("retries", 0);
  record.quality = line.value("quality", nlohmann::json(nullptr));
  record.child_ran = record.status != BatchStatus::skipped;
  return record;
}

BatchLog::BatchLog(const std::filesystem::path& path, bool append)
    : path_(path), file_(path, append ? std::ios::app : std::ios::trunc) {
  if (!file_) throw CliFailure(ExitCode::environment, path.string() + ": cannot be written");
}

void BatchLog::write(const BatchRecord& record) {
  file_ << log_line(record).dump() << '\n' << std::flush;
  if (!file_) throw CliFailure(ExitCode::environment, path_.string() + ": cannot be written");
}

std::set<std::string> outputs_written_with_defects(const std::filesystem::path& path) {
  constexpr int kWrittenWithDefects = static_cast<int>(ExitCode::invalid_result);
  std::map<std::string, int> last_exit_code;
  std::ifstream file(path);
  for (std::string line; std::getline(file, line);) {
    const nlohmann::json record = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    if (!record.is_object() || !record.contains("output") || !record["output"].is_string() ||
        !record.contains("exit_code") || !record["exit_code"].is_number_integer() ||
        record.value("status", "") == to_string(BatchStatus::skipped))
      continue;
    last_exit_code[record["output"].get<std::string>()] = record["exit_code"].get<int>();
  }
  std::set<std::string> defective;
  for (const auto& [output, exit_code] : last_exit_code)
    if (exit_code == kWrittenWithDefects) defective.insert(output);
  return defective;
}

BatchTally::BatchTally(std::size_t inputs, int jobs) : inputs_(inputs), jobs_(jobs) {}

void BatchTally::add(const BatchRecord& record) {
  switch (record.status) {
    case BatchStatus::ok:
      ++ok_;
      break;
    case BatchStatus::failed:
      ++failed_;
      break;
    case BatchStatus::skipped:
      ++skipped_;
      break;
  }
  finished_.push_back({record.input, record.status, record.error, record.seconds, record.child_ran});
}

double BatchTally::elapsed_seconds() const {
  if (elapsed_override_) return *elapsed_override_;
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

// Over the inputs a child ran for: a skipped input, or one whose process could not start, took
// no time of its own and would only pull the mean down.
double BatchTally::mean_seconds_per_file() const {
  double total = 0.0;
  std::size_t run = 0;
  for (const Finished& input : finished_) {
    if (!input.child_ran) continue;
    total += input.seconds;
    ++run;
  }
  return run == 0 ? 0.0 : total / static_cast<double>(run);
}

std::vector<const BatchTally::Finished*> BatchTally::slowest(std::size_t count) const {
  std::vector<const Finished*> run;
  for (const Finished& input : finished_)
    if (input.child_ran) run.push_back(&input);
  std::stable_sort(run.begin(), run.end(),
                   [](const Finished* a, const Finished* b) { return a->seconds > b->seconds; });
  if (run.size() > count) run.resize(count);
  return run;
}

std::string BatchTally::progress_text(std::size_t running) const {
  const std::size_t done = ok_ + failed_ + skipped_;
  const std::size_t run = ok_ + failed_;
  const int filled =
      inputs_ == 0 ? kProgressBarWidth : static_cast<int>(kProgressBarWidth * done / inputs_);
  // Appended piece by piece: `"[" + std::string(...)` trips a GCC 12 -Wrestrict false alarm.
  std::string text(1, '[');
  text.append(static_cast<std::size_t>(filled), '#');
  text.append(static_cast<std::size_t>(kProgressBarWidth - filled), '.');
  text += "] ";
  text += std::to_string(done) + "/" + std::to_string(inputs_) + ": " + std::to_string(ok_) +
          " ok, " + std::to_string(failed_) + " failed, " + std::to_string(skipped_) +
          " skipped; " + std::to_string(running) + " running";
  // The inputs left (running or not started) at the mean seconds per input so far, `jobs_` at a
  // time: an estimate that changes only when an input finishes, not while one runs.
  if (run > 0) {
    const std::size_t left = inputs_ - done;
    const double parallel = static_cast<double>(std::min(left, static_cast<std::size_t>(jobs_)));
    text += "; ETA " +
            duration_text(
                left == 0 ? 0.0 : mean_seconds_per_file() * static_cast<double>(left) / parallel);
  }
  if (const std::vector<const Finished*> slowest_one = slowest(1); !slowest_one.empty()) {
    text += "; slowest " + std::filesystem::path(slowest_one.front()->input).filename().string() +
            " " + duration_text(slowest_one.front()->seconds);
  }
  return text;
}

void BatchTally::print_summary(std::ostream& out, const std::filesystem::path& log) const {
  FieldTable table;
  table.add("inputs", static_cast<long long>(inputs_));
  table.add("ok", static_cast<long long>(ok_));
  table.add("failed", static_cast<long long>(failed_));
  table.add("skipped", static_cast<long long>(skipped_));
  table.add("jobs", jobs_);
  table.add_number("seconds", elapsed_seconds());
  table.add_number("seconds per file", mean_seconds_per_file());
  for (const Finished* input : slowest(kSlowestListed))
    table.add("slowest", input->input + " (" + format_number(input->seconds) + " s)");
  std::size_t listed = 0;
  for (const Finished& input : finished_) {
    if (input.status != BatchStatus::failed) continue;
    if (listed++ == kFailuresListed) {
      table.add("failure",
                "... (" + std::to_string(failed_ - kFailuresListed) + " more in the log)");
      break;
    }
    table.add("failure", input.input + ": " + input.error);
  }
  table.add("log", log.string());
  table.print(out);
}

nlohmann::json BatchTally::summary_json(const std::filesystem::path& log) const {
  nlohmann::json slowest_inputs = nlohmann::json::array();
  for (const Finished* input : slowest(kSlowestListed))
    slowest_inputs.push_back({{"input", input->input}, {"seconds", input->seconds}});
  nlohmann::json failures = nlohmann::json::array();
  for (const Finished& input : finished_)
    if (input.status == BatchStatus::failed)
      failures.push_back({{"input", input.input}, {"error", input.error}});
  return {
      {"status", failed_ == 0 ? "ok" : "failed"},
      {"inputs", inputs_},
      {"ok", ok_},
      {"failed", failed_},
      {"skipped", skipped_},
      {"jobs", jobs_},
      {"seconds", elapsed_seconds()},
      {"seconds_per_file", mean_seconds_per_file()},
      {"slowest", slowest_inputs},
      {"failures", failures},
      {"log", log.string()},
  };
}

}  // namespace harmonia::cli
