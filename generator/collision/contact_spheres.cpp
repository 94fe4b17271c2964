#include "collision/contact_spheres.hpp"

#include <fmt/format.h>

namespace mbgen::gen {

std::vector<ContactSphere> contact_spheres(const Description& d) {
  std::vector<ContactSphere> spheres;
  if (!d.scene || !d.scene->contact) return spheres;
  for (const std::string& link : d.scene->contact->links) {
    // The loader checked that the link exists and has SSVs (load_extras.cpp, read_contact).
    const Frame& frame = d.model.frame(d.model.frame_index(link));
    const std::vector<SsvPrimitive>& compound = d.ssv.at(link);
    for (std::size_t k = 0; k < compound.size(); ++k)
      for (std::size_t v = 0; v < compound[k].points.size(); ++v)
        spheres.push_back({frame.body, frame.X_BF.act(compound[k].points[v]), compound[k].radius, fmt::format("{}/{}/{}", link, k, v)});
  }
  return spheres;
}

}  // namespace mbgen::gen
