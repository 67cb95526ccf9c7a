// Wavefront OBJ meshes for scene files: positions and faces only, triangulated.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "integrands/scenes/scene_math.h"

namespace pcbench::scene {

using TriangleCorners = std::array<Vec3, 3>;

// The triangles of the OBJ file at `path`, in its own coordinates and winding. Its materials,
// normals and texture coordinates are ignored. Throws InputError("<where>: <reason>") when the
// file cannot be read, tinyobjloader rejects it (its message is included), a face refers to a
// vertex that does not exist, or it has no faces.
std::vector<TriangleCorners> load_obj_triangles(const std::filesystem::path& path,
                                                const std::string& where);

}  // namespace pcbench::scene
