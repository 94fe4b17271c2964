#include "fuzz_inputs.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

#include "collision/collision_scene.hpp"
#include "load/load_error.hpp"
#include "model/load_description.hpp"

#ifndef MBGEN_FUZZ_ANKLE_URDF
#error "MBGEN_FUZZ_ANKLE_URDF: the URDF the extras target reads its YAML against"
#endif

namespace mbgen::fuzz {

namespace {

/// A folder of this process's own (nothing else writes there: no robot.yaml to pick up).
const std::string& folder() {
  static const std::string dir = [] {
    std::string pattern = "/tmp/mbgen_fuzz_XXXXXX";
    if (!::mkdtemp(pattern.data())) std::abort();
    return pattern;
  }();
  return dir;
}

std::string write(const std::string& name, const char* data, std::size_t size) {
  const std::string path = folder() + "/" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(data, static_cast<std::streamsize>(size));
  return path;
}

gen::LoadOptions options(const std::string& extras = "") {
  gen::LoadOptions o;
  o.pick_up_robot_yaml = false;
  if (!extras.empty()) o.extras_file = extras;
  return o;
}

template <typename F> bool expecting_load_errors(F&& f) {
  try {
    f();
    return true;
  } catch (const gen::LoadError&) {
    return false;  // bad input, said so: the expected outcome
  }
}

}  // namespace

bool urdf(const std::uint8_t* data, std::size_t size) {
  const std::string path = write("robot.urdf", reinterpret_cast<const char*>(data), size);
  return expecting_load_errors([&] { gen::read_description(path, options()); });
}

bool mjcf(const std::uint8_t* data, std::size_t size) {
  const std::string path = write("robot.xml", reinterpret_cast<const char*>(data), size);
  return expecting_load_errors([&] { gen::read_description(path, options()); });
}

bool extras(const std::uint8_t* data, std::size_t size) {
  const std::string path = write("extras.yaml", reinterpret_cast<const char*>(data), size);
  return expecting_load_errors([&] { gen::read_description(MBGEN_FUZZ_ANKLE_URDF, options(path)); });
}

bool inspect(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t split = text.find(kExtrasSeparator);
  const std::string urdf_path = write("robot.urdf", text.data(), split == std::string::npos ? size : split);
  std::string extras_path;
  if (split != std::string::npos) {
    const std::size_t from = split + std::string(kExtrasSeparator).size();
    extras_path = write("robot_extras.yaml", text.data() + from, size - from);
  }
  return expecting_load_errors([&] {
    const gen::Description d = gen::load_description(urdf_path, options(extras_path));
    gen::CollisionSceneOptions scene = gen::collision_scene_options(d);
    scene.samples = std::min(scene.samples, 200);
    gen::build_collision_scene(d, scene);
  });
}

}  // namespace mbgen::fuzz
