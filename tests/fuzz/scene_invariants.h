// What every successfully loaded scene must satisfy, whatever the file said:
// indices in range, arrays of matching sizes, finite geometry within the
// loader's coordinate limit, unit normals, non-negative colours. The fuzz
// harness and the regression replay check it after each load that succeeds.
#pragma once

#include <string>

#include "kernels/scene/scene.h"

namespace pt::fuzz {

/// Empty if `s` is consistent; otherwise one line describing the first violation.
std::string scene_invariant_violation(const Scene& s);

/// Empty if `message` is a valid loader message for a file labelled `label`:
/// one line (no control characters), starting with the label, at most 1000 bytes.
std::string message_violation(const std::string& message, const std::string& label);

}  // namespace pt::fuzz
