#pragma once
#include <string>

namespace facesr {

// v with `significant` digits ("%.*g": "0.1", "1e+30", "nan", "inf"), the
// form error messages and text outputs use for values.
std::string number_text(double v, int significant = 9);

}  // namespace facesr
