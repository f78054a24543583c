#pragma once
// The scene a simulation runs: distinct LOD chains with their profiles, and the instances placing
// them (SceneAssets, built by acuity::bake::load_scene_assets). This header is the one place sim/
// reaches the bake.
#include "acuity/bake/chains.hpp"
#include "acuity/bake/scene.hpp"

namespace acuity::sim {
using bake::Asset;
using bake::Instance;
using bake::SceneAssets;
}  // namespace acuity::sim
