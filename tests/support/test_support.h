// Helpers shared by the test suites: where scenes live, loading them, and what
// a test does when the shared data (../shared next to the clone: the public
// CS184 scenes, the course's reference images) is absent: it skips, naming the
// missing folder; with CI=true it fails instead, naming it (CI clones the
// project next to ../shared, so there its absence is a broken setup).
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "io/collada_loader.h"

namespace pt::test {

/// Path of a public CS184 scene, e.g. shared_scene("CBbunny.dae").
std::filesystem::path shared_scene(const std::string& name);
/// The folder of the public CS184 scenes (../shared/scenes/cs184).
std::filesystem::path shared_scenes_dir();
/// The folder of the course renderer's reference images (../shared/refs/course).
std::filesystem::path shared_course_refs_dir();
/// Whether the public scenes are present. When they are not and CI=true, also
/// adds a failure to the running test naming the missing folder, so a test that
/// leaves the scenes out of its list where they are absent still fails in CI.
bool shared_scenes_available();

/// Whether the environment says this is a CI run (CI=true or CI=1): there a
/// missing ../shared folder fails the tests that need it instead of skipping them.
bool ci_requires_shared_data();
/// The one-line message for a missing shared folder, naming it and what to do.
std::string missing_shared_message(const std::filesystem::path& folder);
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

/// Ends the current test when the shared folder `folder` is absent: a skip,
/// or with CI=true a failure; either names the folder.
#define PT_REQUIRE_SHARED_DIR(folder)                                               \
  do {                                                                              \
    const std::filesystem::path pt_required_folder_ = (folder);                     \
    if (!std::filesystem::is_directory(pt_required_folder_)) {                      \
      if (::pt::test::ci_requires_shared_data())                                    \
        GTEST_FAIL() << ::pt::test::missing_shared_message(pt_required_folder_);    \
      else GTEST_SKIP() << ::pt::test::missing_shared_message(pt_required_folder_); \
    }                                                                               \
  } while (0)

/// Ends the current test when the public scenes are absent (PT_REQUIRE_SHARED_DIR).
#define PT_REQUIRE_SHARED_SCENES() PT_REQUIRE_SHARED_DIR(::pt::test::shared_scenes_dir())
