#include "perf/livelink_csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/number_text.h"
#include "perf/perf_limits.h"

namespace facesr {
namespace {

using namespace perf_limits;
constexpr size_t kRunsListed = 6;   // a warning names this many runs of lines, then counts the rest

std::string trim(const std::string& s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  std::istringstream in(line);
  while (std::getline(in, field, ',')) out.push_back(trim(field));
  if (!line.empty() && line.back() == ',') out.emplace_back();  // getline drops a trailing empty field
  return out;
}

// Strict decimal: the whole text, finite (strtod alone would accept "nan", "inf", "1.5x" as 1.5).
bool parse_number(const std::string& s, double& v) {
  if (s.empty()) return false;
  for (char c : s)
    if (!(std::isdigit(static_cast<unsigned char>(c)) || c == '.' || c == '-' || c == '+' || c == 'e' || c == 'E'))
      return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

bool parse_uint(const std::string& s, int& v) {
  if (s.empty() || s.size() > 6) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  v = std::atoi(s.c_str());
  return true;
}

// "HH:MM:SS:FF.fff" (FF frames at the capture rate, .fff a fraction of a
// frame) or plain seconds; `where` names the line and column for errors.
// `plain` is cleared for a clock timecode.
double parse_time(const std::string& s, double capture_fps, const std::string& where, bool& plain) {
  double seconds = 0;
  plain = plain && s.find(':') == std::string::npos;
  if (s.find(':') == std::string::npos) {
    require(parse_number(s, seconds), where + ": '" + s + "' is not a timecode (HH:MM:SS:FF.fff) or seconds");
    return seconds;
  }
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, ':')) parts.push_back(part);
  int h = 0, m = 0, sec = 0;
  double frame = 0;
  const bool ok = parts.size() == 4 && parse_uint(parts[0], h) && parse_uint(parts[1], m) &&
                  parse_uint(parts[2], sec) && parse_number(parts[3], frame) && parts[3][0] != '-' &&
                  parts[3][0] != '+';
  require(ok, where + ": '" + s + "' is not a timecode HH:MM:SS:FF.fff (or seconds)");
  require(m < 60 && sec < 60, where + ": '" + s + "' has minutes or seconds above 59");
  require(std::floor(frame) < capture_fps,
          where + ": frame " + number_text(std::floor(frame), 6) + " in '" + s + "' is not below the capture rate " +
              number_text(capture_fps, 6) + " fps (is the capture fps right?)");
  return h * 3600.0 + m * 60.0 + sec + frame / capture_fps;
}

bool is_head_rotation(const std::string& c) {
  const std::string l = lower(c);
  return l == "headyaw" || l == "headpitch" || l == "headroll";
}

bool is_eye_rotation(const std::string& c) {
  const std::string l = lower(c);
  for (const char* eye : {"lefteye", "righteye"})
    for (const char* axis : {"yaw", "pitch", "roll"})
      if (l == std::string(eye) + axis) return true;
  return false;
}

bool ends_with(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// Rig shapes an ARKit column drives: the lowerCamelCase name itself, its ICT
// "_L"/"_R" form, or, for a column with no side, both ICT halves.
std::vector<size_t> shapes_for_column(const std::string& column, const std::map<std::string, size_t>& slot) {
  std::string camel = column;
  camel[0] = char(std::tolower(static_cast<unsigned char>(camel[0])));
  if (auto it = slot.find(camel); it != slot.end()) return {it->second};
  for (const auto& [side, ict] : {std::pair<std::string, std::string>{"Left", "_L"}, {"Right", "_R"}})
    if (ends_with(camel, side)) {
      const auto it = slot.find(camel.substr(0, camel.size() - side.size()) + ict);
      return it != slot.end() ? std::vector<size_t>{it->second} : std::vector<size_t>{};
    }
  std::vector<size_t> out;
  for (const char* ict : {"_L", "_R"})
    if (auto it = slot.find(camel + ict); it != slot.end()) out.push_back(it->second);
  return out;
}

struct Line {
  int number;  // 1-based line in the file
  std::string text;
};

std::vector<Line> read_lines(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  require(in.good(), path + ": cannot open Live Link CSV file (no such file or not readable)");
  std::vector<Line> lines;
  std::string text;
  int number = 0;
  while (std::getline(in, text)) {
    ++number;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (number == 1 && text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 byte order mark
    if (trim(text).empty()) continue;
    lines.push_back({number, text});
  }
  return lines;
}

void check_options(const std::string& path, const LiveLinkOptions& o) {
  require(o.capture_fps > 0 && o.capture_fps <= kMaxFps,
          path + ": capture fps " + number_text(o.capture_fps, 6) + " is not in (0, 1000]");
  require(o.out_fps > 0 && o.out_fps <= kMaxFps,
          path + ": output fps " + number_text(o.out_fps, 6) + " is not in (0, 1000]");
  require(o.weight_tolerance >= 1 && o.weight_tolerance <= 2,
          path + ": weight tolerance " + number_text(o.weight_tolerance, 6) + " is not in [1, 2]");
}

struct Columns {
  std::vector<std::string> header;
  int time = -1;                            // header index of Timecode, -1 without one
  std::vector<int> weights;                 // header index of each mapped column
  std::vector<std::vector<size_t>> shapes;  // rig shapes of each mapped column
};

// Decides what each header column is and fills the report's column lists.
Columns read_header(const std::string& path, const Line& line, const std::vector<std::string>& rig_names,
                    LiveLinkReport& report) {
  Columns cols;
  cols.header = split_fields(line.text);
  std::map<std::string, size_t> slot;
  for (size_t i = 0; i < rig_names.size(); ++i) slot.emplace(rig_names[i], i);
  std::map<size_t, std::string> driven_by;
  std::map<std::string, int> seen;
  for (size_t c = 0; c < cols.header.size(); ++c) {
    const std::string& name = cols.header[c];
    const std::string where = path + ": line " + std::to_string(line.number) + ": header column " +
                              std::to_string(c + 1);
    require(!name.empty(), where + " has no name");
    const auto [first, fresh] = seen.emplace(name, int(c));
    require(fresh, where + ": '" + name + "' repeats column " + std::to_string(first->second + 1));
    if (lower(name) == "timecode") {
      cols.time = int(c);
    } else if (lower(name) == "blendshapecount") {
      report.ignored.push_back({name, "metadata (number of blendshapes)"});
    } else if (is_head_rotation(name)) {
      report.ignored.push_back({name, "head rotation (the rig has no neck)"});
    } else if (is_eye_rotation(name)) {
      report.ignored.push_back({name, "eye rotation (the rig's eyes do not rotate)"});
    } else if (const std::vector<size_t> shapes = shapes_for_column(name, slot); !shapes.empty()) {
      LiveLinkReport::Mapped m{name, {}};
      for (size_t s : shapes) {
        const auto [it, fresh] = driven_by.emplace(s, name);
        require(fresh, where + ": '" + name + "' and '" + it->second + "' would both drive rig shape '" +
                           rig_names[s] + "'");
        m.shapes.push_back(rig_names[s]);
      }
      report.mapped.push_back(std::move(m));
      cols.weights.push_back(int(c));
      cols.shapes.push_back(shapes);
    } else {
      report.unknown.push_back(name);
    }
  }
  for (size_t s = 0; s < rig_names.size(); ++s)
    if (!driven_by.count(s)) report.shapes_without_column.push_back(rig_names[s]);
  report.has_timecode = cols.time >= 0;
  return cols;
}

void add_line(LiveLinkReport::LineRanges& runs, int line) {
  if (!runs.empty() && runs.back().second + 1 == line)
    runs.back().second = line;
  else
    runs.push_back({line, line});
}

// One weight field, clamped into [0, 1] when lenient mode accepts it.
double read_weight(const std::string& text, const std::string& at, const std::string& column, int line,
                   const LiveLinkOptions& o, LiveLinkReport& report) {
  // Messages are built only on failure: a take has ~10^5 weights.
  auto where = [&] { return at + ": column '" + column + "': '" + text + "'"; };
  double v = 0;
  if (!parse_number(text, v)) throw Error(where() + " is not a number");
  if (v >= 0 && v <= 1) return v;
  if (o.strict) throw Error(where() + " is outside the weight range [0, 1] (strict mode clamps nothing)");
  const double low = 1 - o.weight_tolerance, high = o.weight_tolerance;
  if (v < low || v > high)
    throw Error(where() + " is outside the weight range [0, 1] by more than the tolerance (only weights in [" +
                number_text(low, 6) + ", " + number_text(high, 6) + "] are clamped)");
  if (report.clamped_values++ == 0) {
    report.first_clamped_line = line;
    report.first_clamped_column = column;
    report.first_clamped_value = v;
  }
  auto overshoot = [](double x) { return x < 0 ? -x : x - 1; };
  if (report.clamped_values == 1 || overshoot(v) > overshoot(report.farthest_clamped_value))
    report.farthest_clamped_value = v;
  return std::clamp(v, 0.0, 1.0);
}

// The rows kept for resampling. Tracking-lost rows keep their time (a loss at
// either end still counts toward the take's length) and get their weights
// from fill_lost_rows.
struct Rows {
  std::vector<int> line;
  std::vector<double> time;    // seconds, or the Timecode's number until frame indices are detected
  std::vector<char> lost;
  std::vector<double> values;  // rows × mapped columns
  bool plain = true;           // no time was a clock timecode

  void push(int l, double t, bool is_lost, const std::vector<double>& w) {
    line.push_back(l);
    time.push_back(t);
    lost.push_back(is_lost);
    values.insert(values.end(), w.begin(), w.end());
  }
  void pop(size_t nw) {
    line.pop_back();
    time.pop_back();
    lost.pop_back();
    values.resize(values.size() - nw);
  }
};

Rows read_rows(const std::string& path, const std::vector<Line>& lines, const Columns& cols,
               const LiveLinkOptions& o, LiveLinkReport& report) {
  const size_t nw = cols.weights.size(), nh = cols.header.size();
  Rows rows;
  rows.time.reserve(lines.size());
  rows.values.reserve(lines.size() * nw);
  std::vector<double> w(nw, 0.0);
  for (size_t r = 1; r < lines.size(); ++r) {
    const int number = lines[r].number;
    const std::string at = path + ": line " + std::to_string(number);
    const std::vector<std::string> fields = split_fields(lines[r].text);
    const bool lost = fields.size() < nh;
    if (fields.size() > nh || (lost && o.strict))
      throw Error(at + ": has " + std::to_string(fields.size()) + " fields, the header has " + std::to_string(nh) +
                  (lost ? " (tracking lost? strict mode refuses such rows; the default interpolates over them)"
                        : ""));
    if (lost) {
      ++report.tracking_lost_rows;
      add_line(report.tracking_lost_lines, number);
      if (cols.time >= int(fields.size())) continue;  // not even its time: nothing to place
    }
    const double t = cols.time >= 0 ? parse_time(fields[size_t(cols.time)], o.capture_fps,
                                                 at + ": column '" + cols.header[size_t(cols.time)] + "'", rows.plain)
                                    : double(r - 1) / o.capture_fps;
    std::fill(w.begin(), w.end(), 0.0);
    if (!lost)
      for (size_t c = 0; c < nw; ++c) {
        const size_t f = size_t(cols.weights[c]);
        w[c] = read_weight(fields[f], at, cols.header[f], number, o, report);
      }
    if (!rows.time.empty() && t <= rows.time.back()) {
      require(t == rows.time.back() && !o.strict,
              at + ": time " + number_text(t, 6) + " s is not after line " + std::to_string(rows.line.back()) +
                  "'s " + number_text(rows.time.back(), 6) + " s (times must increase)");
      // A repeated time: keep the first tracked row of that instant.
      if (lost) continue;
      if (!rows.lost.back()) {
        ++report.repeated_time_rows;
        add_line(report.repeated_time_lines, number);
        continue;
      }
      rows.pop(nw);
    }
    rows.push(number, t, lost, w);
  }
  return rows;
}

// A frame counter in a column meant for seconds: every time whole, at least
// 3 rows, the smallest step exactly 1 (see the header for why).
bool frame_indices(const Rows& rows) {
  if (!rows.plain || rows.time.size() < 3) return false;
  double step = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < rows.time.size(); ++i) {
    if (rows.time[i] != std::floor(rows.time[i])) return false;
    if (i > 0) step = std::min(step, rows.time[i] - rows.time[i - 1]);
  }
  return step == 1;
}

// Gives tracking-lost rows the weights of the tracked rows around them:
// linear in time between the two, the nearest held at either end of the take.
void fill_lost_rows(Rows& rows, size_t nw, bool& held_start, bool& held_end) {
  const size_t n = rows.time.size();
  for (size_t i = 0; i < n;) {
    if (!rows.lost[i]) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < n && rows.lost[j]) ++j;  // run [i, j) lost; i - 1 and j tracked where they exist
    held_start = held_start || i == 0;
    held_end = held_end || j == n;
    const double* a = i > 0 ? rows.values.data() + (i - 1) * nw : rows.values.data() + j * nw;
    const double* b = j < n ? rows.values.data() + j * nw : a;
    for (size_t k = i; k < j; ++k) {
      const double alpha = i > 0 && j < n ? (rows.time[k] - rows.time[i - 1]) / (rows.time[j] - rows.time[i - 1]) : 0;
      double* v = rows.values.data() + k * nw;
      for (size_t c = 0; c < nw; ++c) v[c] = a[c] + alpha * (b[c] - a[c]);
    }
    i = j;
  }
}

// "lines 384-512, 1713-1835" (the first kRunsListed runs, then a count).
std::string describe_lines(const LiveLinkReport::LineRanges& runs) {
  std::string s = runs.size() == 1 && runs[0].first == runs[0].second ? "line " : "lines ";
  for (size_t i = 0; i < runs.size() && i < kRunsListed; ++i) {
    s += (i ? ", " : "") + std::to_string(runs[i].first);
    if (runs[i].second != runs[i].first) s += "-" + std::to_string(runs[i].second);
  }
  if (runs.size() > kRunsListed) s += " and " + std::to_string(runs.size() - kRunsListed) + " more runs";
  return s;
}

// "1 row", "277 rows".
std::string count_of(int n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

std::vector<std::string> warnings(const LiveLinkReport& r, const LiveLinkOptions& o, bool held_start,
                                  bool held_end) {
  std::vector<std::string> out;
  if (r.clamped_values > 0)
    out.push_back(count_of(r.clamped_values, "weight") + " outside [0, 1] clamped (first at line " +
                  std::to_string(r.first_clamped_line) + ", column '" + r.first_clamped_column +
                  "': " + number_text(r.first_clamped_value, 6) + "; farthest " +
                  number_text(r.farthest_clamped_value, 6) + ")");
  if (r.tracking_lost_rows > 0) {
    std::string s = count_of(r.tracking_lost_rows, "tracking-lost row") + " (" +
                    describe_lines(r.tracking_lost_lines) + ") interpolated between the tracked rows around them";
    if (held_start && held_end)
      s += "; those at the start and end of the take hold the nearest tracked row";
    else if (held_start || held_end)
      s += held_start ? "; those at the start of the take hold the first tracked row"
                      : "; those at the end of the take hold the last tracked row";
    out.push_back(s);
  }
  if (r.repeated_time_rows > 0)
    out.push_back(count_of(r.repeated_time_rows, "row") + " repeating the previous row's time (" +
                  describe_lines(r.repeated_time_lines) + ") dropped");
  if (r.timecode == LiveLinkTimecode::FrameIndex)
    out.push_back("the Timecode column counts frames (whole numbers stepping by 1), not seconds: read as frames at " +
                  number_text(o.capture_fps, 6) + " fps");
  return out;
}

// Performance frames at out_fps from the first row's time, linear between rows.
Performance resample(const std::string& path, const Rows& rows, const Columns& cols,
                     const std::vector<std::string>& rig_names, double out_fps) {
  const std::vector<double>& times = rows.time;
  const size_t nw = cols.weights.size();
  const double span = (times.back() - times.front()) * out_fps;
  require(span < kMaxFrames, path + ": the take spans " + number_text(times.back() - times.front(), 6) +
                                 " s, more than " + number_text(kMaxFrames, 6) + " frames at " + number_text(out_fps, 6) +
                                 " fps (a broken timecode?)");
  Performance p;
  p.name = std::filesystem::path(path).stem().string();
  p.fps = out_fps;
  p.start_time = 0;
  p.names = rig_names;
  const int frames = int(std::floor(span + 1e-6)) + 1;
  p.weights.assign(size_t(frames) * rig_names.size(), 0.0f);
  size_t k = 0;
  for (int f = 0; f < frames; ++f) {
    const double t = std::min(times.front() + f / out_fps, times.back());
    while (k + 1 < times.size() && times[k + 1] <= t) ++k;
    double alpha = k + 1 < times.size() ? (t - times[k]) / (times[k + 1] - times[k]) : 0.0;
    // Snap onto rows up to rounding so a take already at out_fps is copied exactly.
    if (alpha <= 1e-9) alpha = 0;
    if (alpha >= 1 - 1e-9) alpha = 1;
    const double* a = rows.values.data() + k * nw;
    const double* b = k + 1 < times.size() ? a + nw : a;
    float* row = p.weights.data() + size_t(f) * rig_names.size();
    for (size_t c = 0; c < nw; ++c) {
      const float v = float(alpha == 1 ? b[c] : a[c] + alpha * (b[c] - a[c]));
      for (size_t s : cols.shapes[c]) row[s] = v;
    }
  }
  return p;
}

}  // namespace

const char* livelink_timecode_name(LiveLinkTimecode t) {
  switch (t) {
    case LiveLinkTimecode::None: return "none";
    case LiveLinkTimecode::Clock: return "clock";
    case LiveLinkTimecode::Seconds: return "seconds";
    case LiveLinkTimecode::FrameIndex: return "frame_index";
  }
  return "?";
}

Performance load_livelink_csv(const std::string& path, const std::vector<std::string>& rig_names,
                              const LiveLinkOptions& o, LiveLinkReport* report_out) {
  check_options(path, o);
  const std::vector<Line> lines = read_lines(path);
  require(!lines.empty(), path + ": is empty (expected a Live Link Face header line and rows)");
  LiveLinkReport report;
  report.strict = o.strict;
  const Columns cols = read_header(path, lines[0], rig_names, report);
  require(lines.size() > 1, path + ": has a header but no data rows");
  report.rows = int(lines.size() - 1);

  Rows rows = read_rows(path, lines, cols, o, report);
  require(std::count(rows.lost.begin(), rows.lost.end(), 0) > 0,
          path + ": no tracked rows: all " + std::to_string(report.rows) +
              " data rows have fewer fields than the header (tracking lost for the whole take)");
  report.timecode = cols.time < 0  ? LiveLinkTimecode::None
                    : rows.plain   ? LiveLinkTimecode::Seconds
                                   : LiveLinkTimecode::Clock;
  if (cols.time >= 0 && frame_indices(rows)) {
    require(!o.strict, path + ": column '" + cols.header[size_t(cols.time)] +
                           "' holds whole numbers stepping by 1 (lines " + std::to_string(rows.line.front()) + "-" +
                           std::to_string(rows.line.back()) +
                           "): frame indices, not seconds; strict mode refuses to guess (the default reads them as "
                           "frames at " + number_text(o.capture_fps, 6) + " fps)");
    report.timecode = LiveLinkTimecode::FrameIndex;
    for (double& t : rows.time) t /= o.capture_fps;
  }
  bool held_start = false, held_end = false;
  fill_lost_rows(rows, cols.weights.size(), held_start, held_end);
  report.first_time_s = rows.time.front();
  report.last_time_s = rows.time.back();
  Performance p = resample(path, rows, cols, rig_names, o.out_fps);
  report.warnings = warnings(report, o, held_start, held_end);
  if (report_out) *report_out = std::move(report);
  return p;
}

nlohmann::json livelink_report_json(const LiveLinkReport& r) {
  nlohmann::json mapped = nlohmann::json::object(), ignored = nlohmann::json::object();
  for (const auto& m : r.mapped) mapped[m.column] = m.shapes;
  for (const auto& i : r.ignored) ignored[i.column] = i.reason;
  auto runs = [](const LiveLinkReport::LineRanges& lr) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& [first, last] : lr) a.push_back({first, last});
    return a;
  };
  nlohmann::json j = {{"rows", r.rows},
                      {"has_timecode", r.has_timecode},
                      {"timecode_mode", livelink_timecode_name(r.timecode)},
                      {"strict", r.strict},
                      {"first_time_s", r.first_time_s},
                      {"last_time_s", r.last_time_s},
                      {"mapped_columns", r.mapped.size()},
                      {"ignored_columns", r.ignored.size()},
                      {"unknown_columns", r.unknown.size()},
                      {"mapped", mapped},
                      {"ignored", ignored},
                      {"unknown", r.unknown},
                      {"shapes_without_column", r.shapes_without_column},
                      {"clamped_values", r.clamped_values},
                      {"tracking_lost_rows", r.tracking_lost_rows},
                      {"tracking_lost_lines", runs(r.tracking_lost_lines)},
                      {"repeated_time_rows", r.repeated_time_rows},
                      {"repeated_time_lines", runs(r.repeated_time_lines)},
                      {"warnings", r.warnings}};
  if (r.clamped_values > 0)
    j["first_clamped"] = {{"line", r.first_clamped_line},
                          {"column", r.first_clamped_column},
                          {"value", r.first_clamped_value},
                          {"farthest_value", r.farthest_clamped_value}};
  return j;
}

std::string livelink_report_summary(const LiveLinkReport& r) {
  auto list = [](const std::vector<std::string>& names) {
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
  };
  std::string s = std::to_string(r.mapped.size()) + " columns mapped, " + std::to_string(r.ignored.size()) +
                  " ignored (head/eye rotations, metadata), " + std::to_string(r.unknown.size()) + " unknown";
  if (!r.unknown.empty()) s += " (" + list(r.unknown) + ")";
  s += "; " + std::to_string(r.shapes_without_column.size()) + " rig shapes have no column";
  if (!r.shapes_without_column.empty()) s += " (" + list(r.shapes_without_column) + ")";
  return s;
}

}  // namespace facesr
