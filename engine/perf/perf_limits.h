#pragma once
#include <cctype>
#include <string>

// Limits every performance reader shares (keyframe JSON, Live Link CSV).
namespace facesr::perf_limits {

constexpr double kMaxFps = 1000;
// Two hours at 30 fps: longer than any take or cinematic a face is driven
// by. The bound is on memory as much as on sense: a 60-byte keyframe file or
// a four-row capture with a broken timecode must not make a reader allocate
// gigabytes and interpolate for seconds (found by fuzzing: a one-digit
// timecode typo spanned 10 hours, 1.1 million frames). At the limit a
// 53-shape performance holds 46 MB.
constexpr double kMaxFrames = 216000;

inline std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace facesr::perf_limits
