#pragma once
// The scene a simulation runs: distinct LOD chains with their profiles, and the instances placing
// them (SceneAssets, built by load_scene_assets). They come from the offline bake, which still
// lives in tools/scene_assets while it moves to acuity::bake; this header is the one place sim/
// reaches it.
#include "level_input.hpp"
#include "scene_assets.hpp"

namespace acuity::sim {
using tools::Asset;
using tools::Instance;
using tools::level_input;
using tools::SceneAssets;
}  // namespace acuity::sim
