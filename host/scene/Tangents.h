// Tangent frames for normal maps on primitives without a TANGENT attribute.
#pragma once

#include "../Vec3.h"

#include <cstdint>
#include <vector>

namespace wv {

// MikkTSpace tangents (Mikkelsen, "Simulation of wrinkled surfaces
// revisited", 2008; what the glTF specification recommends and what Blender
// and most bakers write) of an indexed triangle list: per triangle corner
// (4 floats for corner c of `indices`) x, y, z along +u and the handedness
// w = ±1 such that cross(normal, tangent)·w points along −v, "up" in the
// texture image, the +Y of glTF's normal textures. `normals` (per vertex) may
// be empty: the corners then get their triangle's normal, as glTF's flat
// shading has it. A corner where MikkTSpace leaves the tangent undefined
// (no texture coordinates, or none of its triangles has a usable UV mapping)
// gets some unit direction perpendicular to its normal.
std::vector<float> mikkTSpaceTangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                      const std::vector<float>& uvs, const std::vector<uint32_t>& indices);

} // namespace wv
