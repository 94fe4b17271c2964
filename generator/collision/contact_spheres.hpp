#pragma once
// The spheres that touch the ground in a simulation (sim/contact.hpp): the vertices of the SSVs
// of the links the scene lists under `contact: links`, moved into their bodies' frames.
#include <vector>

#include "load/description.hpp"
#include "mbgen/contact_model.hpp"

namespace mbgen::gen {

/// In the order of the scene's links, then of each link's SSVs, then of their vertices; named
/// "<link>/<ssv index>/<vertex index>". Empty when the scene has no `contact`.
std::vector<ContactSphere> contact_spheres(const Description& d);

}  // namespace mbgen::gen
