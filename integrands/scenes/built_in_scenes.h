// The scenes pcbench ships, built in code (so the binary needs no data files):
//   cornell         a closed diffuse box (red and green side walls), a square area light just
//                   under the ceiling, two blocks
//   cornell-glossy  the same with a normalised-Phong floor and tall block
//   door-ajar       two rooms joined by a door standing ajar; the light is in the far room, so
//                   the camera's room is lit only through the narrow gap
//   lampshade       a room lit by a small lamp that faces up inside a shade open at both ends:
//                   the camera sees no emitter, and the shade blocks nearly every connection
//                   from the room to the bulb or to a first light bounce
//   many-lights     a room lit by 100 small ceiling lights whose radiances span two orders of
//                   magnitude; the strongest sit in an alcove behind a partition or in deep cans,
//                   so from most of the floor the lights chosen by power are hidden (where
//                   resampled next-event estimation should beat plain next-event estimation)
//   furnace         a closed box whose walls all emit Le and reflect with albedo ρ: every pixel
//                   sees exactly Le · Σ_{k<L} ρ^k (furnace_radiance)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

const std::vector<std::string>& built_in_scene_names();

// The named scene, or nothing when there is no built-in scene of that name.
std::optional<SceneDescription> built_in_scene(const std::string& name);

// The furnace's emission and albedo, and its exact radiance for maximum path length L.
inline constexpr Rgb kFurnaceEmission = {1.0, 0.5, 0.25};
inline constexpr double kFurnaceAlbedo = 0.5;
Rgb furnace_radiance(std::uint32_t max_length);

}  // namespace pcbench::scene
