// The built-in procedural scenes (DESIGN §9; Chong & Gortler §3-4). Deterministic: the same
// parameters give bit-identical meshes on every run.
#pragma once

#include <lixel/scene/scene.h>
#include <lixel/solver/result.h>

#include <optional>
#include <string>
#include <vector>

namespace lixel::scene {

// The paper's room: floor y = 0 and wall z = -5 as planes of interest (floor first), with a
// sphere, a box, a torus and a lathe-turned cone bouncing on the floor. `time` in seconds moves
// them (each bounces with its own period); time 0 is the default view.
Scene FloorWallScene(double time = 0.0);

// The same room as meshes that never change and a pose per time (what a live engine sends):
// the shapes built resting on the floor, each lifted by its bounce height at `time` through its
// instance (floor and wall in place). The shapes' meshes are FloorWallScene's at a bounce height
// of 0, so a posed frame matches FloorWallScene(time) up to float rounding of the vertices.
Scene FloorWallAnimated(double time = 0.0);

// The paper's table/floor configuration: a table top (bounded plane of interest, a convex
// polygon) over a floor (infinite plane, second priority), with casters on the table.
Scene TableFloorScene();

// A 10 x 10 grid of spheres on a floor, tessellated so the whole scene has close to
// `triangles` triangles (clamped to [30'000, 2'000'000]; the result is within 2% of the target).
Scene SphereGridScene(long triangles = 100'000);

// Thin plates over a floor: open zero-thickness quads (two-sided for visibility and shadows, as
// paper 003 treats open surfaces) and closed slabs 1 mm thick, the case where
// second-depth shadow maps are ambiguous (paper 003).
Scene ThinPlatesScene();

// A coarse sphere and a coarse torus with smooth vertex normals over a floor: silhouettes that
// smooth shadow volumes (paper 002) must round off.
// `refinement` multiplies every tessellation count: the same sphere and torus, finer; a fine
// copy is the smooth objects' ground truth (docs/volumes.md).
Scene SphereTorusScene(int refinement = 1);

// Lathe-turned pins standing on a floor: curved receivers that no plane of interest covers.
// `refinement` multiplies the slices and the ball's tessellation and samples the pins' outline
// that many times per span on the Catmull-Rom curve through its points: the same pins, finer.
Scene PinsScene(int refinement = 1);

// The perspective-aliasing test bed of Lloyd et al. (2008): a 400 m floor, the viewer 1.7 m
// above it looking along it (near 0.5 m, far 200 m), a directional light from above and behind,
// and posts as casters from 4 m to 128 m away (docs/eval.md compares the measured aliasing of
// every method with their analysis).
Scene LongFloorScene();

// The scenes whose casters are smooth objects (closed, with vertex normals) coarsely
// tessellated, "sphere_torus" and "pins", with those casters `refinement` times finer and the
// rest (floor, camera, light, mesh order) the same: the smooth objects' ground truth (issue 16).
// nullopt for every other name.
std::optional<Scene> SmoothTwin(const std::string& name, int refinement = 8);

// SmoothTwin(scene.name) when `scene` has that built-in scene's meshes as built in; nullopt for
// any other scene, one that only shares a built-in name (a file) included.
std::optional<Scene> SmoothTwinOf(const Scene& scene, int refinement = 8);

// Names accepted by BuiltinScene, in a fixed order; the first is the default scene.
std::vector<std::string> BuiltinSceneNames();

// A built-in scene by name ("floor_wall", "table_floor", "sphere_grid", "thin_plates",
// "sphere_torus", "pins", "long_floor") with its default parameters. Error names the scene.
Result<Scene> BuiltinScene(const std::string& name);

}  // namespace lixel::scene
