// A scene as Blender Python that builds it in Cycles, for `pcbench export SCENE --to cycles`
// (harness/commands/export_command.h): scene.py (the scene and every setting), render.py (R
// replicates with distinct seeds into float EXR files).
//
// Units and conventions, pcbench's and their Cycles equivalents (each checked by rendering with
// Debian's Blender 3.4 in the ci test `export.cycles`, tests/export_cycles_check.py: the furnace
// against its exact image, cornell against pcbench's `pt`):
// - Geometry: the triangles as they are, in the same units and right-handed coordinates (pcbench
//   has y up, Blender z up: only the camera's orientation matters, and it is given in the same
//   coordinates). One mesh per (material, emission) pair; flat shading, no smoothing.
// - Emission is radiance: a triangle emitting Le is an Emission shader of Color Le / max(Le) and
//   Strength max(Le), which Cycles renders as radiance Color × Strength. One-sided: pcbench's
//   emitters radiate into the hemisphere of cross(p1 - p0, p2 - p0), which is Blender's face
//   normal for the same vertex order; Cycles' emission is two-sided, so a Geometry Backfacing
//   mix leaves the back side without emission. Scattering is two-sided in both.
// - Materials: diffuse is the Diffuse BSDF with roughness 0 (Lambertian, albedo / π); mirror is
//   the Glossy BSDF with the Sharp distribution (a perfect reflection × albedo, no Fresnel).
//   pcbench's normalised Phong lobe has no Cycles equivalent: refused (its glossy BSDFs are
//   microfacet models), written with --approximate as a Beckmann lobe of roughness
//   (2 / (n + 2))^(1/4).
// - Point lights: refused (Cycles gives them in Blender watts, a convention no test here has
//   checked against pcbench's radiant intensity); --approximate writes a radius-0 point light of
//   energy 4π × intensity.
// - Camera: a pinhole with pcbench's vertical field of view (sensor fit Vertical, angle_y) and
//   basis (right = forward × up), W × H pixels of aspect 1; the top image row is y = 0 in both.
//   Near clip 1e-6, no shift, no motion blur, no depth of field.
// - Pixel: pcbench's pixel value is the mean radiance over the pixel's square on the image plane,
//   which is Cycles' Box pixel filter of width 1 px (the default is Blackman-Harris, 1.5 px).
// - Path length: pcbench's max_length L counts segments from the camera to the emitter (L = 1:
//   emitters seen directly); Cycles' max_bounces B counts bounces after the first hit and always
//   adds direct light there, so its paths have at most B + 2 segments: B = L - 2 for the total
//   and for each kind (diffuse, glossy, transmission, transparent; volume 0). L = 1 has no
//   Cycles setting: refused. Cycles ends paths by Russian roulette after min_light_bounces (0
//   here, Blender's default), which is unbiased; pcbench's walks have none, so the two differ in
//   variance and cost per sample, not in expectation (docs/findings/cycles-cost.md measures it).
// - Unbiased and independent replicates: adaptive sampling off, light threshold 0, clamping off
//   (direct and indirect), filter glossy 0, caustics on, denoising off, path guiding off, no
//   animated seed, scrambling distance 1, seed = first seed + replicate; the world is black.
// - Output: linear radiance as 32-bit float OpenEXR, RGB (no alpha), ZIP (lossless); the
//   Standard view transform (an EXR gets no view transform anyway).
#pragma once

#include <string>
#include <vector>

#include "integrands/scenes/scene_description.h"

namespace pcbench::scene {

// What Cycles cannot represent exactly: the material, light or setting, and why.
struct InexactPart {
  std::string what;
  std::string why;
};

// Every part of `scene` that Cycles would render differently from pcbench (in the order of the
// description: materials used by some triangle, point lights, the path length).
std::vector<InexactPart> cycles_inexact_parts(const SceneDescription& scene);

// scene.py: the scene's data (resolution, path length, camera, materials, triangles grouped by
// material and emission, point lights) and `build(scene)`, which builds it with every setting
// above into an empty Blender scene. Inexact parts are written as approximations.
std::string cycles_scene_script(const SceneDescription& scene);

// scene.py's fixed part after its data block: the functions that build the scene (Python text,
// cycles_python.cpp).
const char* cycles_scene_functions();

// render.py: `blender -b -P render.py -- --replicates R --spp N --out FOLDER [--threads T]
// [--first-seed S]` builds scene.py (beside it) and writes FOLDER/cycles_rep<k>.exr, k = 000 ...
// R - 1, with seeds S + k (S = 1 by default); exit 2 on bad arguments (FOLDER exists and is not
// empty: an earlier render's files would join the set), 1 on a failed render.
std::string cycles_render_script();

}  // namespace pcbench::scene
