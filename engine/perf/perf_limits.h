#pragma once
#include <cctype>
#include <string>

// Limits every performance reader shares (keyframe JSON, Live Link CSV).
namespace facesr::perf_limits {

constexpr double kMaxFps = 1000;
// A day at 30 fps: far beyond any real take, small enough to catch a typo
// or a broken timecode.
constexpr double kMaxFrames = 3e6;

inline std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace facesr::perf_limits
