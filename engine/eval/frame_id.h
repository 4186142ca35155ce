#pragma once
#include <string>

namespace facesr {

// Which test frame a row of results belongs to: the performance (dataset
// sequence) name and the frame's index in that sequence.
struct FrameId {
  std::string sequence;
  int frame = 0;
};

}  // namespace facesr
