// Test helper implementations.
#include "support/test_support.h"

#include <cstdlib>
#include <cstring>

#include "io/read_file.h"

namespace pt::test {

std::filesystem::path shared_scene(const std::string& name) { return std::filesystem::path(PT_SHARED_SCENES) / name; }

std::filesystem::path shared_scenes_dir() { return std::filesystem::path(PT_SHARED_SCENES); }

std::filesystem::path shared_course_refs_dir() {
  return shared_scenes_dir().parent_path().parent_path() / "refs" / "course";
}

bool ci_requires_shared_data() {
  const char* ci = std::getenv("CI");
  return ci && (std::strcmp(ci, "true") == 0 || std::strcmp(ci, "1") == 0);
}

std::string missing_shared_message(const std::filesystem::path& folder) {
  std::string what = folder.lexically_normal().string() + " is missing (the shared data, ../shared next to the clone)";
  return ci_requires_shared_data() ? what + "; CI=true: a CI run needs it" : what + "; skipped (CI=true fails instead)";
}

bool shared_scenes_available() {
  if (std::filesystem::is_directory(shared_scenes_dir())) return true;
  if (ci_requires_shared_data()) ADD_FAILURE() << missing_shared_message(shared_scenes_dir());
  return false;
}

std::filesystem::path project_scene(const std::string& name) { return std::filesystem::path(PT_PROJECT_SCENES) / name; }
std::filesystem::path test_data(const std::string& name) { return std::filesystem::path(PT_TEST_DATA) / name; }

std::string file_bytes(const std::filesystem::path& path) {
  return read_regular_file(path, "test file", uint64_t(1) << 32);
}

LoadResult load_string(const std::string& xml, const std::string& label) { return load_collada_string(xml, label); }

const std::vector<std::string>& shared_scene_names() {
  static const std::vector<std::string> names = {"CBspheres_lambertian.dae",
                                                 "CBempty.dae",
                                                 "CBgems.dae",
                                                 "CBcoil.dae",
                                                 "CBbunny.dae",
                                                 "bunny.dae",
                                                 "cow.dae",
                                                 "beetle.dae",
                                                 "teapot.dae",
                                                 "banana.dae",
                                                 "CBspheres_microfacet_al_ag.dae",
                                                 "bunny_microfacet_cu.dae"};
  return names;
}

}  // namespace pt::test
