// Test helper implementations.
#include "support/test_support.h"

#include "io/read_file.h"

namespace pt::test {

std::filesystem::path shared_scene(const std::string& name) { return std::filesystem::path(PT_SHARED_SCENES) / name; }

bool shared_scenes_available() { return std::filesystem::is_directory(PT_SHARED_SCENES); }

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
