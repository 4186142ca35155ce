// load_performance: one entry point for every performance file the tools
// accept, so commands need not know the formats.
#include <cctype>
#include <cstdio>
#include <filesystem>

#include "core/error.h"
#include "perf/livelink_csv.h"
#include "perf/performance.h"

namespace facesr {

Performance load_performance(const std::string& path, const std::vector<std::string>& rig_names,
                             LiveLinkReport* csv_report) {
  return load_performance(path, rig_names, LiveLinkOptions(), csv_report);
}

Performance load_performance(const std::string& path, const std::vector<std::string>& rig_names,
                             const LiveLinkOptions& csv, LiveLinkReport* csv_report) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".json") return load_performance_json(path, rig_names);
  if (ext == ".csv") return load_livelink_csv(path, rig_names, csv, csv_report);
  throw Error(path + ": unknown performance file type '" + ext +
              "' (expected .json keyframes or .csv Live Link Face capture)");
}

Performance load_performance_warned(const std::string& path, const std::vector<std::string>& rig_names,
                                    const LiveLinkOptions& csv, const std::string& tag, LiveLinkReport* csv_report) {
  LiveLinkReport own;
  LiveLinkReport& report = csv_report ? *csv_report : own;
  Performance p = load_performance(path, rig_names, csv, &report);
  for (const std::string& w : report.warnings)
    std::fprintf(stderr, "[%s] %s: warning: %s\n", tag.c_str(), path.c_str(), w.c_str());
  return p;
}

}  // namespace facesr
