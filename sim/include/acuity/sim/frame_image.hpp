#pragma once
// Pictures of simulated frames: the head's view in perspective with every object drawn at the level
// a rule chose, coloured by level (0 blue, 1 cyan, 2 green, 3 yellow, 4 orange, 5 red, then purple
// and grey), shaded by a headlight; the gaze marked by a ring of 2 deg radius and the level colours
// as swatches in the lower left. Panels side by side compare rules on the same frame.
#include <cstdint>
#include <string>
#include <vector>

#include "acuity/sim/simulation.hpp"

namespace acuity::sim {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // RGB8, row 0 at the top
};

// Draws frame `frame` of the simulation with each object at levels[object] into the panel of `image`
// whose left edge is x0 (panels are image.height square).
void draw_levels(const Simulation& sim, std::size_t frame, const std::uint8_t* levels, RgbImage* image,
                 int x0);

// PNG, written atomically. Throws std::runtime_error naming the path.
void write_png(const std::string& path, const RgbImage& image);

}  // namespace acuity::sim
