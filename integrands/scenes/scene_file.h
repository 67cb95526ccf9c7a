// Scene files: JSON describing a triangle scene, read into a SceneDescription.
//
// Units are arbitrary; coordinates are right-handed with y up. Every vector is [x, y, z] and
// every colour [r, g, b], three finite numbers each.
//
//   {
//     "name": "cornell",               // optional, default the file name without extension
//     "description": "any text",       // optional, ignored
//     "camera": {"position": [0, 1, 3], "look_at": [0, 1, 0],
//                "up": [0, 1, 0],      // optional, default [0, 1, 0]; not parallel to the view
//                "fov": 40},           // optional, vertical degrees in (0, 180), default 45
//     "resolution": 32,                // optional: N (N x N) or "WxH"; W, H in [1, 8192]; 32
//     "max_length": 5,                 // optional, path segments, integer in [1, 64]; 5
//     "materials": {                   // name -> material; albedo channels in [0, 1]
//       "white": {"type": "diffuse", "albedo": [0.7, 0.7, 0.7]},
//       "shiny": {"type": "phong", "albedo": [0.5, 0.5, 0.5], "exponent": 40},  // exponent > 0
//       "glass": {"type": "mirror", "albedo": [0.9, 0.9, 0.9]}
//     },
//     "shapes": [                      // at least one; "material" names a material above;
//                                      // "emission" (optional, >= 0) is front-side radiance
//       {"type": "quad", "corners": [p0, p1, p2, p3], "material": "white"},
//       {"type": "triangle", "corners": [p0, p1, p2], "material": "white", "emission": [9, 9, 9]},
//       {"type": "box", "min": [..], "max": [..], "material": "white",
//        "normals": "outward"},        // or "inward" (an enclosure seen from inside); outward
//       {"type": "mesh", "positions": [p, ...], "indices": [[i, j, k], ...], "material": "white"},
//       {"type": "obj", "file": "bunny.obj", "material": "white",
//        "scale": 1.0, "translate": [0, 0, 0]}  // optional; position = scale * p + translate
//     ],
//     "point_lights": [{"position": [..], "intensity": [r, g, b]}]  // optional, intensity >= 0
//   }
//
// A triangle's front side, the side it emits into, is the one its normal cross(p1 - p0, p2 - p0)
// points to. A quad is the triangles (p0, p1, p2) and (p0, p2, p3). An "obj" file is read with
// tinyobjloader and triangulated; a relative path is relative to the scene file's folder, and its
// own materials are ignored (the shape's "material" applies).
//
// Everything is checked before anything is traced: unknown keys, types and material names (with
// the valid choices), repeated keys, degenerate triangles, an unusable camera, and a scene that
// emits nothing.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

// Throws pcbench::InputError("<source_name>:<line:column>: ..." for JSON syntax, otherwise
// "<source_name>: <JSON pointer>: <reason>") on any bad input. `base_dir` resolves relative
// "obj" paths.
SceneDescription parse_scene_json(std::string_view text, const std::string& source_name,
                                  const std::filesystem::path& base_dir);

// Reads and parses `path`; a missing or unreadable file is an InputError too.
SceneDescription read_scene_file(const std::filesystem::path& path);

}  // namespace pcbench::scene
