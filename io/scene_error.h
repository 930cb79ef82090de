// The one exception type of io/: a bad scene, camera file or output path. Its
// message is a single line naming the file and the element, ready to print.
#pragma once

#include <stdexcept>
#include <string>

namespace pt {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace pt
