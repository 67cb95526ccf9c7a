#include "integrands/scenes/scene_obj.h"

#include <fmt/format.h>
#include <tiny_obj_loader.h>

#include <string>

#include "base/errors.h"
#include "base/text_file.h"

namespace pcbench::scene {
namespace {

// tinyobjloader's messages end in newlines and sometimes hold several lines.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

tinyobj::ObjReader parse_obj(const std::string& text, bool triangulate, const std::string& where,
                             const std::string& shown_path) {
  tinyobj::ObjReaderConfig config;
  config.triangulate = triangulate;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  // From a string with no material text: the file's "mtllib" is never opened, since the
  // scene's material applies to the whole mesh.
  if (!reader.ParseFromString(text, "", config)) {
    throw InputError(fmt::format("{}: OBJ file '{}' cannot be loaded: {}", where, shown_path,
                                 one_line(reader.Error())));
  }
  return reader;
}

// tinyobjloader only warns about a vertex index past the end, keeps such triangles and may
// read out of bounds when it triangulates larger polygons; so indices are checked on the
// untriangulated faces before it triangulates them.
void check_indices(const tinyobj::ObjReader& reader, const std::string& where,
                   const std::string& shown_path) {
  const std::size_t vertex_count = reader.GetAttrib().vertices.size() / 3;
  std::size_t face_number = 0;  // 1-based over the whole file, as OBJ counts vertices
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    std::size_t next = 0;
    for (const unsigned corners : shape.mesh.num_face_vertices) {
      ++face_number;
      for (unsigned k = 0; k < corners; ++k, ++next) {
        const int index = shape.mesh.indices[next].vertex_index;
        if (index < 0 || static_cast<std::size_t>(index) >= vertex_count) {
          throw InputError(fmt::format(
              "{}: OBJ file '{}': face {} refers to vertex {} but the file has {} vertices", where,
              shown_path, face_number, index + 1, vertex_count));
        }
      }
    }
  }
}

}  // namespace

std::vector<TriangleCorners> load_obj_triangles(const std::filesystem::path& path,
                                                const std::string& where) {
  const std::string shown_path = path.string();
  std::string text;
  try {
    text = read_text_file(path, "the OBJ file");
  } catch (const InputError& e) {
    // Also name the scene key that refers to the file.
    throw InputError(fmt::format("{}: {}", where, e.what()));
  }
  check_indices(parse_obj(text, false, where, shown_path), where, shown_path);
  const tinyobj::ObjReader reader = parse_obj(text, true, where, shown_path);
  const std::vector<tinyobj::real_t>& v = reader.GetAttrib().vertices;
  const auto vertex = [&](const tinyobj::index_t& index) {
    const auto i = static_cast<std::size_t>(index.vertex_index) * 3;
    return Vec3{v[i], v[i + 1], v[i + 2]};
  };
  std::vector<TriangleCorners> triangles;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    const std::vector<tinyobj::index_t>& indices = shape.mesh.indices;
    for (std::size_t i = 0; i + 2 < indices.size(); i += 3) {
      triangles.push_back({vertex(indices[i]), vertex(indices[i + 1]), vertex(indices[i + 2])});
    }
  }
  if (triangles.empty()) {
    throw InputError(fmt::format("{}: OBJ file '{}' has no faces", where, shown_path));
  }
  return triangles;
}

}  // namespace pcbench::scene
