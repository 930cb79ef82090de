// Helpers shared by the test suites: where scenes live, loading them, and
// skipping cleanly when the public CS184 scenes are not present.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "io/collada_loader.h"

namespace pt::test {

/// Path of a public CS184 scene, e.g. shared_scene("CBbunny.dae").
std::filesystem::path shared_scene(const std::string& name);
bool shared_scenes_available();
/// Path of one of this project's scenes.
std::filesystem::path project_scene(const std::string& name);
/// Path of a file under tests/data, e.g. test_data("blender/spot_blend.dae").
std::filesystem::path test_data(const std::string& name);

/// Loads a scene from a COLLADA string (for small hand-written test files).
LoadResult load_string(const std::string& xml, const std::string& label = "test.dae");

/// The bytes of a file the test wrote or expects (the tests' one reader:
/// read_regular_file, io/read_file.h); throws InputError when it cannot.
std::string file_bytes(const std::filesystem::path& path);

/// The names of all public CS184 scenes, in a fixed order.
const std::vector<std::string>& shared_scene_names();

}  // namespace pt::test

/// Skips the current test when the public scenes are absent.
#define PT_REQUIRE_SHARED_SCENES()                                                  \
  do {                                                                              \
    if (!::pt::test::shared_scenes_available()) GTEST_SKIP() << "../shared absent"; \
  } while (0)
