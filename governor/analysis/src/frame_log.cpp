#include "glbudget/analysis/frame_log.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <string_view>
#include <utility>

namespace glbudget::analysis {

using namespace glbudget::model;
namespace {

constexpr double kNotMeasured = std::numeric_limits<double>::quiet_NaN();

std::vector<std::string_view> split_fields(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    std::string_view field = line.substr(start, comma - start);
    if (field.size() >= 2 && field.front() == '"' && field.back() == '"') {
      field = field.substr(1, field.size() - 2);
    }
    fields.push_back(field);
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

// Empty: not measured (NaN). Otherwise a number, or nullopt when malformed.
std::optional<double> parse_measurement(std::string_view field) {
  if (field.empty()) return kNotMeasured;
  double value = 0.0;
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (error != std::errc{} || end != field.data() + field.size()) return std::nullopt;
  return value;
}

struct Columns {
  static constexpr int kAbsent = -1;
  int frame = kAbsent, time_ns = kAbsent, context = kAbsent, pass = kAbsent;
  int batches = kAbsent, vertices = kAbsent, fragments = kAbsent, primitives = kAbsent;
  int gpu_ns = kAbsent, power_w = kAbsent, energy_j = kAbsent, sensor = kAbsent;
  int configuration = kAbsent, probe_streams = kAbsent;
};

Columns locate_columns(const std::vector<std::string_view>& header) {
  Columns c;
  const std::pair<const char*, int*> names[] = {
      {"frame", &c.frame},
      {"time_ns", &c.time_ns},
      {"context", &c.context},
      {"pass", &c.pass},
      {"batches", &c.batches},
      {"vertices", &c.vertices},
      {"fragments", &c.fragments},
      {"primitives", &c.primitives},
      {"gpu_ns", &c.gpu_ns},
      {"power_w", &c.power_w},
      {"energy_j", &c.energy_j},
      {"sensor", &c.sensor},
      {"configuration", &c.configuration},
      {"probe_streams", &c.probe_streams},
  };
  for (std::size_t i = 0; i < header.size(); ++i) {
    for (const auto& [name, index] : names) {
      if (header[i] == name) *index = static_cast<int>(i);
    }
  }
  return c;
}

class RowParser {
 public:
  RowParser(const std::vector<std::string_view>& fields) : fields_(fields) {}

  std::string_view text(int column) const {
    return column >= 0 && static_cast<std::size_t>(column) < fields_.size() ? fields_[column] : std::string_view{};
  }
  // NaN when the column is absent or empty; records a problem when malformed.
  double number(int column, const char* name) {
    const std::optional<double> value = parse_measurement(text(column));
    if (!value && problem_.empty()) problem_ = std::string("bad ") + name;
    return value.value_or(kNotMeasured);
  }
  const std::string& problem() const { return problem_; }

 private:
  const std::vector<std::string_view>& fields_;
  std::string problem_;
};

}  // namespace

std::optional<FrameLog> read_frame_log(std::istream& in, const std::string& source) {
  std::string line;
  if (!std::getline(in, line)) {
    std::cerr << "glbudget: " << source << ": empty frame log\n";
    return std::nullopt;
  }
  const Columns columns = locate_columns(split_fields(line));
  if (columns.frame < 0 || columns.pass < 0 || columns.batches < 0 || columns.vertices < 0 || columns.fragments < 0) {
    std::cerr << "glbudget: " << source << ": not a frame log (needs columns frame,pass,batches,vertices,fragments)\n";
    return std::nullopt;
  }

  FrameLog log;
  std::map<std::pair<std::string, std::uint64_t>, std::size_t> frame_index;  // (context, frame)
  std::size_t line_number = 1;
  std::size_t first_bad_line = 0;
  std::string first_problem;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line == "\r") continue;
    ++log.rows;
    const std::vector<std::string_view> fields = split_fields(line);
    RowParser row(fields);
    const double frame_number = row.number(columns.frame, "frame");
    LoggedPass pass{std::string(row.text(columns.pass)),
                    {row.number(columns.batches, "batches"), row.number(columns.vertices, "vertices"),
                     row.number(columns.fragments, "fragments")},
                    row.number(columns.primitives, "primitives"),
                    row.number(columns.gpu_ns, "gpu_ns")};
    const double time_ns = row.number(columns.time_ns, "time_ns");
    const double power_w = row.number(columns.power_w, "power_w");
    const double energy_j = row.number(columns.energy_j, "energy_j");
    std::string problem = row.problem();
    // Below 2^64: a larger frame number (1e300, inf) does not fit the uint64_t it becomes.
    if (problem.empty() &&
        !(frame_number >= 0.0 && frame_number < 0x1p64 && frame_number == std::floor(frame_number))) {
      problem = "bad frame number";
    }
    if (problem.empty() && pass.pass.empty()) problem = "empty pass";
    if (!problem.empty()) {
      if (log.rows_skipped++ == 0) first_bad_line = line_number, first_problem = problem;
      continue;
    }

    const auto key = std::make_pair(std::string(row.text(columns.context)), static_cast<std::uint64_t>(frame_number));
    auto [it, inserted] = frame_index.try_emplace(key, log.frames.size());
    if (inserted) {
      log.frames.push_back({key.second,
                            time_ns,
                            key.first,
                            {},
                            kNotMeasured,
                            kNotMeasured,
                            std::string(row.text(columns.sensor)),
                            std::string(row.text(columns.configuration)),
                            std::string(row.text(columns.probe_streams))});
    }
    LoggedFrame& frame = log.frames[it->second];
    // Power is per frame; take the first row that carries it.
    if (std::isnan(frame.power_w)) frame.power_w = power_w;
    if (std::isnan(frame.energy_j)) frame.energy_j = energy_j;
    frame.passes.push_back(std::move(pass));
  }
  if (log.rows_skipped > 0) {
    std::cerr << "glbudget: " << source << ": skipped " << log.rows_skipped << " malformed row(s), first at line "
              << first_bad_line << " (" << first_problem << ")\n";
  }
  return log;
}

std::optional<FrameLog> read_frame_log_file(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "glbudget: cannot read frame log " << path << "\n";
    return std::nullopt;
  }
  return read_frame_log(in, path);
}

std::vector<LoggedFrame> frames_of_busiest_context(const FrameLog& log) {
  std::map<std::string, std::size_t> frames_per_context;
  for (const LoggedFrame& frame : log.frames) ++frames_per_context[frame.context];
  std::string busiest;
  std::size_t most = 0;
  for (const auto& [context, count] : frames_per_context) {
    if (count > most) busiest = context, most = count;
  }
  std::vector<LoggedFrame> frames;
  for (const LoggedFrame& frame : log.frames) {
    if (frame.context == busiest) frames.push_back(frame);
  }
  return frames;
}

}  // namespace glbudget::analysis
