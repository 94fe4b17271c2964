#pragma once
// The data behind `scripts/ssv_picture.sh`'s PNG: a robot's meshes and its SSV compounds at the
// nominal pose, for gnuplot to draw from three sides.
#include <string>
#include <vector>

#include "load/fit_link_ssvs.hpp"

namespace mbgen::cli {

/// Writes DIR/mesh.dat (each triangle in world coordinates, x y z, closed, one block each) and
/// DIR/ssv.dat (three indices, front y-z, side x-z, top x-y: each primitive's silhouette as a
/// closed outline, one block each) for the pose q (nq; the neutral pose, or the closed assembly).
/// Throws std::runtime_error if the files cannot be written.
void write_ssv_picture_data(const std::string& directory, const gen::Description& d, const std::vector<gen::LinkFit>& fits);

}  // namespace mbgen::cli
