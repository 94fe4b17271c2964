#pragma once
// What MuJoCo would have to load from disk, taken out of an MJCF document: the <asset> section,
// mesh geoms and materials (the robot files' meshes are not in ../shared/robots). Every body of
// those files has an <inertial>, so no inertia changes. Shared by the MuJoCo peer test and the
// side-by-side simulation (examples/sim/mujoco_side_by_side.cpp).
#include <tinyxml2.h>

#include <string>
#include <vector>

namespace mbgen::test {

inline void remove_mujoco_assets(tinyxml2::XMLDocument& doc) {
  tinyxml2::XMLElement* root = doc.FirstChildElement("mujoco");
  if (!root) return;
  if (auto* asset = root->FirstChildElement("asset")) root->DeleteChild(asset);
  std::vector<tinyxml2::XMLElement*> stack{root};
  while (!stack.empty()) {
    tinyxml2::XMLElement* e = stack.back();
    stack.pop_back();
    e->DeleteAttribute("material");
    for (tinyxml2::XMLElement* c = e->FirstChildElement(); c;) {
      tinyxml2::XMLElement* next = c->NextSiblingElement();
      if (std::string(c->Name()) == "geom" && c->Attribute("mesh")) e->DeleteChild(c);
      else stack.push_back(c);
      c = next;
    }
    // A default that makes geoms meshes would need a mesh: make them spheres (visual only).
    if (std::string(e->Name()) == "geom" && e->Attribute("type", "mesh")) e->SetAttribute("type", "sphere");
  }
}

}  // namespace mbgen::test
