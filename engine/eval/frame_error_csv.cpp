#include "eval/frame_error_csv.h"

#include <cmath>
#include <cstdio>

#include "core/atomic_file.h"
#include "core/error.h"

namespace facesr {
namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

}  // namespace

void check_frame_table(const std::vector<FrameId>& frames, const std::vector<std::string>& methods,
                       const std::vector<std::vector<double>>& frame_means, const std::string& who) {
  require(!methods.empty(), who + ": no methods given");
  require(!frames.empty(), who + ": no test frames given");
  require(frame_means.size() == methods.size(), who + ": " + std::to_string(methods.size()) + " methods but " +
                                                    std::to_string(frame_means.size()) + " columns of errors");
  for (size_t m = 0; m < methods.size(); ++m) {
    require(frame_means[m].size() == frames.size(), who + ": method '" + methods[m] + "' has " +
                                                        std::to_string(frame_means[m].size()) + " frame errors for " +
                                                        std::to_string(frames.size()) + " test frames");
    for (size_t f = 0; f < frames.size(); ++f)
      if (!std::isfinite(frame_means[m][f]))
        throw Error(who + ": method '" + methods[m] + "', frame " + std::to_string(f) + ": the error is not finite");
  }
}

void write_frame_error_csv(std::ostream& out, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods,
                           const std::vector<std::vector<double>>& frame_means) {
  check_frame_table(frames, methods, frame_means, "frame error CSV");
  out << "sequence,frame";
  for (const std::string& m : methods) out << ',' << csv_field(m + "_mean_cm");
  out << '\n';
  char buf[32];
  for (size_t f = 0; f < frames.size(); ++f) {
    out << csv_field(frames[f].sequence) << ',' << frames[f].frame;
    for (size_t m = 0; m < methods.size(); ++m) {
      std::snprintf(buf, sizeof buf, "%.9g", frame_means[m][f]);
      out << ',' << buf;
    }
    out << '\n';
  }
}

void write_frame_error_csv(const std::string& path, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods,
                           const std::vector<std::vector<double>>& frame_means) {
  check_frame_table(frames, methods, frame_means, "frame error CSV '" + path + "'");
  write_file_atomically(path, [&](std::ostream& out) { write_frame_error_csv(out, frames, methods, frame_means); });
}

}  // namespace facesr
