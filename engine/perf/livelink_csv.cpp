#include "perf/livelink_csv.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/number_text.h"

namespace facesr {
namespace {

constexpr double kMaxFps = 1000;
constexpr double kMaxFrames = 3e6;  // as for keyframe JSON: catches a broken timecode, not a real take
// ARKit weights overshoot [0, 1] by rounding; anything further is not a weight.
constexpr double kTolerance = 0.01;

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

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
double parse_time(const std::string& s, double capture_fps, const std::string& where) {
  double seconds = 0;
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

}  // namespace

Performance load_livelink_csv(const std::string& path, const std::vector<std::string>& rig_names, double capture_fps,
                              double out_fps, LiveLinkReport* report_out) {
  require(capture_fps > 0 && capture_fps <= kMaxFps,
          path + ": capture fps " + number_text(capture_fps, 6) + " is not in (0, 1000]");
  require(out_fps > 0 && out_fps <= kMaxFps, path + ": output fps " + number_text(out_fps, 6) + " is not in (0, 1000]");
  const std::vector<Line> lines = read_lines(path);
  require(!lines.empty(), path + ": is empty (expected a Live Link Face header line and rows)");

  // Header: decide what each column is.
  const std::vector<std::string> header = split_fields(lines[0].text);
  std::map<std::string, size_t> slot;
  for (size_t i = 0; i < rig_names.size(); ++i) slot.emplace(rig_names[i], i);
  LiveLinkReport report;
  int time_column = -1;
  std::vector<int> weight_columns;               // header index of each mapped column
  std::vector<std::vector<size_t>> weight_shapes;  // rig shapes of each mapped column
  std::map<size_t, std::string> driven_by;
  std::map<std::string, int> seen;
  for (size_t c = 0; c < header.size(); ++c) {
    const std::string& name = header[c];
    const std::string where = path + ": line " + std::to_string(lines[0].number) + ": header column " +
                              std::to_string(c + 1);
    require(!name.empty(), where + " has no name");
    const auto [first, fresh] = seen.emplace(name, int(c));
    require(fresh, where + ": '" + name + "' repeats column " + std::to_string(first->second + 1));
    if (lower(name) == "timecode") {
      time_column = int(c);
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
      weight_columns.push_back(int(c));
      weight_shapes.push_back(shapes);
    } else {
      report.unknown.push_back(name);
    }
  }
  for (size_t s = 0; s < rig_names.size(); ++s)
    if (!driven_by.count(s)) report.shapes_without_column.push_back(rig_names[s]);
  report.has_timecode = time_column >= 0;
  require(lines.size() > 1, path + ": has a header but no data rows");

  // Rows: time and the mapped columns' weights.
  const size_t nw = weight_columns.size();
  std::vector<double> times, values;
  times.reserve(lines.size() - 1);
  values.reserve((lines.size() - 1) * nw);
  int previous_line = 0;
  for (size_t r = 1; r < lines.size(); ++r) {
    const std::string at = path + ": line " + std::to_string(lines[r].number);
    const std::vector<std::string> fields = split_fields(lines[r].text);
    require(fields.size() == header.size(), at + ": has " + std::to_string(fields.size()) + " fields, the header has " +
                                                std::to_string(header.size()));
    const double t = time_column >= 0
                         ? parse_time(fields[time_column], capture_fps, at + ": column '" + header[time_column] + "'")
                         : double(r - 1) / capture_fps;
    if (!times.empty())
      require(t > times.back(), at + ": time " + number_text(t, 6) + " s is not after line " +
                                    std::to_string(previous_line) + "'s " + number_text(times.back(), 6) +
                                    " s (times must increase)");
    times.push_back(t);
    previous_line = lines[r].number;
    for (int c : weight_columns) {
      const std::string where = at + ": column '" + header[c] + "': '" + fields[c] + "'";
      double v = 0;
      require(parse_number(fields[c], v), where + " is not a number");
      require(v >= -kTolerance && v <= 1 + kTolerance, where + " is outside the weight range [0, 1]");
      values.push_back(std::clamp(v, 0.0, 1.0));
    }
  }
  report.rows = int(times.size());
  report.first_time_s = times.front();
  report.last_time_s = times.back();

  // Resample from the first row's time.
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
    const double* a = values.data() + k * nw;
    const double* b = k + 1 < times.size() ? a + nw : a;
    float* row = p.weights.data() + size_t(f) * rig_names.size();
    for (size_t c = 0; c < nw; ++c) {
      const float v = float(alpha == 1 ? b[c] : a[c] + alpha * (b[c] - a[c]));
      for (size_t s : weight_shapes[c]) row[s] = v;
    }
  }
  if (report_out) *report_out = std::move(report);
  return p;
}

nlohmann::json livelink_report_json(const LiveLinkReport& r) {
  nlohmann::json mapped = nlohmann::json::object(), ignored = nlohmann::json::object();
  for (const auto& m : r.mapped) mapped[m.column] = m.shapes;
  for (const auto& i : r.ignored) ignored[i.column] = i.reason;
  return {{"rows", r.rows},
          {"has_timecode", r.has_timecode},
          {"first_time_s", r.first_time_s},
          {"last_time_s", r.last_time_s},
          {"mapped_columns", r.mapped.size()},
          {"ignored_columns", r.ignored.size()},
          {"unknown_columns", r.unknown.size()},
          {"mapped", mapped},
          {"ignored", ignored},
          {"unknown", r.unknown},
          {"shapes_without_column", r.shapes_without_column}};
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
