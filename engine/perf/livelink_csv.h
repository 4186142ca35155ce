#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "perf/performance.h"

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
// 1/capture_fps apart. Times must strictly increase. The take is resampled
// to out_fps by linear interpolation starting at the first row's time, which
// becomes t = 0 of the performance. Weights must be numbers in
// [-0.01, 1.01] (ARKit overshoots slightly); they are clamped into [0, 1].
namespace facesr {

struct LiveLinkReport {
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
  int rows = 0;             // data rows read
  double first_time_s = 0;  // time of the first row (the performance's t = 0)
  double last_time_s = 0;
};

// Reads a Live Link Face CSV take and resamples it to `out_fps` in the rig's
// blendshape order. Errors name the file and, for a bad row, its line and
// column, e.g. "take.csv: line 7: column 'JawOpen': 'abc' is not a number".
Performance load_livelink_csv(const std::string& path, const std::vector<std::string>& rig_names,
                              double capture_fps = 60, double out_fps = 30, LiveLinkReport* report = nullptr);

// The report as JSON: counts plus the column and shape names.
nlohmann::json livelink_report_json(const LiveLinkReport& r);

// One line for a log: "52 columns mapped, 10 ignored (head/eye rotations,
// BlendShapeCount), 1 unknown (TongueOut); 2 rig shapes have no column".
std::string livelink_report_summary(const LiveLinkReport& r);

}  // namespace facesr
