#pragma once
#include <ostream>
#include <string>
#include <vector>

#include "eval/frame_id.h"

namespace facesr {

// The frame-wise errors behind the paper's fig. 5 as CSV: a header row
//   sequence,frame,<method>_mean_cm,...
// then one row per test frame with each method's mean per-vertex error (cm).
// frame_means[m][f] belongs to methods[m] and frames[f]. Fields holding a
// comma, quote or line break are quoted (RFC 4180). Throws Error on
// mismatched counts or non-finite values, before writing anything.
void write_frame_error_csv(std::ostream& out, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods,
                           const std::vector<std::vector<double>>& frame_means);

// The same, written atomically to `path`.
void write_frame_error_csv(const std::string& path, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods,
                           const std::vector<std::vector<double>>& frame_means);

// Checks shared by the CSV and SVG writers: at least one method and frame,
// frame_means methods x frames, every value finite. `who` prefixes the Error.
void check_frame_table(const std::vector<FrameId>& frames, const std::vector<std::string>& methods,
                       const std::vector<std::vector<double>>& frame_means, const std::string& who);

}  // namespace facesr
