#pragma once
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "perf/performance.h"
#include "sim/controls.h"

// Import of Epic's Live Link Face CSV takes (ARKit face capture on an iPhone).
//
// The file is one header line and one row per captured frame:
//
//   Timecode,BlendShapeCount,EyeBlinkLeft,EyeLookDownLeft,...,TongueOut,HeadYaw,HeadPitch,...
//   19:35:05:27.466,61,0.0512,0.1203,...
//
// Column names are ARKit's in PascalCase with Left/Right suffixes. Each maps
// to the rig shape of the same name in lowerCamelCase ("EyeBlinkLeft" →
// "eyeBlinkLeft") or in ICT style ("eyeBlink_L"), whichever the rig has; an
// ARKit column with no side that the rig splits into _L and _R (CheekPuff,
// BrowInnerUp) drives both halves. Head and eye rotations (HeadYaw, ...,
// RightEyeRoll) and BlendShapeCount are ignored: the rig has no neck and its
// eyes do not rotate. Columns matching no rig shape (e.g. TongueOut on the
// ICT head) are reported and ignored; rig shapes with no column stay 0.
//
// Timecode is "HH:MM:SS:FF.fff" (FF the frame at the capture rate, .fff the
// sub-frame fraction) or plain seconds; without a Timecode column, rows are
// 1/capture_fps apart. Rows may come at a lower rate than the timecode's
// frames (the app often writes 30 Hz rows under a 60 fps timecode, FF
// stepping by 2): only the times matter. Times must not go back. The take is
// resampled to out_fps by linear interpolation starting at the first row's
// time, which becomes t = 0 of the performance.
//
// What the app really emits, and what the default (lenient) mode does with
// it; strict mode (LiveLinkOptions::strict) refuses each of these instead,
// naming the file and line. Every repair is counted in LiveLinkReport and
// described by one line in LiveLinkReport::warnings for the caller to print.
//
//  * Weights slightly outside [0, 1] (ARKit's EyeLookIn reaches 1.05 in
//    range-of-motion takes): values in [-(tol - 1), tol], tol =
//    weight_tolerance (default 1.1, so [-0.1, 1.1]), are clamped into [0, 1].
//    Beyond that, or a non-number, NaN or inf, is an error naming the file,
//    line, column and value in both modes; strict refuses anything outside
//    [0, 1].
//  * Tracking-lost rows: when the phone loses the face the app writes rows
//    with fewer fields than the header (just the timecode and
//    BlendShapeCount 0). They are dropped and their weights interpolated
//    linearly in time between the tracked rows around them; at the start or
//    end of the take they hold the nearest tracked row. Their times still
//    count, so the take keeps its length. A take with no tracked row is an
//    error. A row with more fields than the header is always an error.
//  * Repeated times: a row whose time equals the previous row's is dropped
//    (the first row of that time is kept, or the repeat replaces a
//    tracking-lost row of that time).
//  * Frame indices: a Timecode column of plain numbers that are all whole,
//    at least 3 rows, whose smallest step between rows is exactly 1 is a
//    frame counter, not seconds (no face capture runs at 1 Hz or slower,
//    which whole-second rows would need); it is read as frames at
//    capture_fps rather than played capture_fps times too slow. Skipped
//    indices (dropped frames) are gaps, as in any timecode.
namespace facesr {

struct LiveLinkOptions {
  double capture_fps = 60;  // the timecode's frame rate (FF) and the row rate without a Timecode column
  double out_fps = 30;      // the performance's rate
  bool strict = false;      // refuse instead of repairing (see above)
  // Lenient mode clamps weights in [-(tol - 1), tol] into [0, 1]; in [1, 2].
  double weight_tolerance = kWeightTolerance;  // sim/controls.h: the runtime clamps the same way
};

enum class LiveLinkTimecode {
  None,        // no Timecode column: rows 1/capture_fps apart
  Clock,       // "HH:MM:SS:FF.fff"
  Seconds,     // plain seconds
  FrameIndex,  // plain whole numbers read as frames at capture_fps
};

struct LiveLinkReport {
  using LineRanges = std::vector<std::pair<int, int>>;  // 1-based file lines, first and last of each run
  struct Mapped {
    std::string column;
    std::vector<std::string> shapes;  // rig shapes it drives (two for a split shape)
  };
  struct Ignored {
    std::string column, reason;
  };
  std::vector<Mapped> mapped;
  std::vector<Ignored> ignored;
  std::vector<std::string> unknown;                 // columns matching no rig shape
  std::vector<std::string> shapes_without_column;   // rig shapes nothing drives (stay 0)
  bool has_timecode = false;
  LiveLinkTimecode timecode = LiveLinkTimecode::None;
  bool strict = false;
  int rows = 0;             // data rows in the file, tracking-lost and repeated ones included
  double first_time_s = 0;  // time of the first row (the performance's t = 0)
  double last_time_s = 0;

  // Weights outside [0, 1] clamped (lenient mode): how many, the first, the farthest out.
  int clamped_values = 0;
  int first_clamped_line = 0;
  std::string first_clamped_column;
  double first_clamped_value = 0, farthest_clamped_value = 0;
  int tracking_lost_rows = 0;
  LineRanges tracking_lost_lines;
  int repeated_time_rows = 0;  // dropped for repeating the previous row's time
  LineRanges repeated_time_lines;
  // One line per kind of repair above, for the caller to print (the library prints nothing).
  std::vector<std::string> warnings;
};

// Reads a Live Link Face CSV take and resamples it to `options.out_fps` in
// the rig's blendshape order. Errors name the file and, for a bad row, its
// line and column, e.g. "take.csv: line 7: column 'JawOpen': 'abc' is not a
// number".
Performance load_livelink_csv(const std::string& path, const std::vector<std::string>& rig_names,
                              const LiveLinkOptions& options = LiveLinkOptions(), LiveLinkReport* report = nullptr);

// The report as JSON: counts, the column and shape names, the timecode kind
// ("none", "clock", "seconds", "frame_index"), the repairs and the warnings.
nlohmann::json livelink_report_json(const LiveLinkReport& r);

// One line for a log: "52 columns mapped, 10 ignored (head/eye rotations,
// BlendShapeCount), 1 unknown (TongueOut); 2 rig shapes have no column".
// The warnings are not in it.
std::string livelink_report_summary(const LiveLinkReport& r);

// "clock", "seconds", ... as in the JSON.
const char* livelink_timecode_name(LiveLinkTimecode t);

}  // namespace facesr
