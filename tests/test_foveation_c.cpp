// The C ABI of the foveation planner (acuity.h): the same maps as the C++ API, bit for bit; its
// contract on sizes, statuses and bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "acuity.h"
#include "acuity/foveation_plan.hpp"

namespace {
acuity_eye c_eye(uint32_t w, uint32_t h, float half_deg) {
  acuity_eye e;
  acuity_eye_default(&e);
  e.fov_deg[0] = -half_deg;
  e.fov_deg[1] = half_deg;
  e.fov_deg[2] = half_deg;
  e.fov_deg[3] = -half_deg;
  e.viewport[0] = w;
  e.viewport[1] = h;
  e.gaze_valid = 1;
  e.gaze_confidence = 1;
  e.gaze_direction[0] = 0.2f;
  e.gaze_direction[1] = -0.1f;
  e.gaze_direction[2] = -0.97f;
  return e;
}
}  // namespace

TEST(FoveationC, SameMapsAsTheCppApi) {
  acuity_foveation_config config;
  acuity_foveation_config_default(&config);
  EXPECT_EQ(config.struct_size, sizeof config);
  config.threshold_model = 1;  // geisler-perry
  config.quality = 0.9f;
  acuity_foveation_planner* planner = nullptr;
  ASSERT_EQ(acuity_foveation_create(&config, &planner), ACUITY_OK);

  const acuity_eye e = c_eye(2000, 1800, 50);
  uint32_t cols = 0, rows = 0;
  ASSERT_EQ(acuity_foveation_map_size(&e, 16, &cols, &rows), ACUITY_OK);
  EXPECT_EQ(cols, 125u);
  EXPECT_EQ(rows, 113u);
  std::vector<uint8_t> rate(2 * cols * rows);
  std::vector<float> bias(cols * rows);
  acuity_foveation_info info;
  ASSERT_EQ(acuity_foveation_plan(planner, &e, 16, cols * rows, rate.data(), bias.data(), &info), ACUITY_OK);
  EXPECT_EQ(info.result, uint32_t(ACUITY_FOVEATION_GAZE));
  EXPECT_EQ(info.cols, cols);
  EXPECT_GT(1.0 - info.shaded / info.pixels, 0.5);

  acuity::FoveationConfig cpp;
  cpp.model = acuity::ThresholdModel::GeislerPerry;
  cpp.quality = 0.9f;
  auto p = std::make_unique<acuity::FoveationPlanner>();
  ASSERT_EQ(acuity::init_foveation_planner(cpp, p.get()), acuity::FoveationStatus::Ok);
  acuity::Eye eye;
  for (int k = 0; k < 4; ++k) eye.fov_deg[k] = e.fov_deg[k];
  eye.viewport[0] = 2000;
  eye.viewport[1] = 1800;
  acuity::Gaze gaze;
  gaze.valid = true;
  for (int k = 0; k < 3; ++k) gaze.direction[k] = e.gaze_direction[k];
  std::vector<uint8_t> rate2(rate.size());
  std::vector<float> bias2(bias.size());
  acuity::FoveationMaps maps;
  maps.tile_px = 16;
  maps.capacity = cols * rows;
  maps.shading_rate = rate2.data();
  maps.mip_bias = bias2.data();
  ASSERT_EQ(acuity::plan_foveation(*p, eye, gaze, &maps), acuity::FoveationStatus::Ok);
  EXPECT_EQ(rate, rate2);
  EXPECT_EQ(bias, bias2);
  EXPECT_EQ(info.shaded, maps.shaded);
  EXPECT_EQ(info.origin_px[0], maps.origin_px[0]);

  acuity_guenter_layers layers;
  ASSERT_EQ(acuity_foveation_layers(planner, &e, 3, &layers), ACUITY_OK);
  const acuity::FoveationLayers l = acuity::foveation_layers(*p, eye, 3);
  EXPECT_EQ(layers.n_layers, 3u);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(layers.radius_deg[i], l.layers.radius[i]);
  EXPECT_EQ(layers.speedup, l.layers.speedup);
  acuity_foveation_destroy(planner);
}

TEST(FoveationC, Contract) {
  acuity_foveation_config config;
  acuity_foveation_config_default(&config);
  acuity_foveation_planner* planner = nullptr;
  config.struct_size = 4;  // an older, shorter struct than this library knows
  EXPECT_EQ(acuity_foveation_create(&config, &planner), ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(planner, nullptr);
  EXPECT_STRNE(acuity_last_error(), "");
  acuity_foveation_config_default(&config);
  config.threshold_model = 9;
  EXPECT_EQ(acuity_foveation_create(&config, &planner), ACUITY_INVALID_ARGUMENT);
  config.threshold_model = ACUITY_MODEL_STELA_CSF + 1;  // the last model is the largest value
  EXPECT_EQ(acuity_foveation_create(&config, &planner), ACUITY_INVALID_ARGUMENT);
  config.threshold_model = ACUITY_MODEL_STELA_CSF;
  ASSERT_EQ(acuity_foveation_create(&config, &planner), ACUITY_OK) << acuity_last_error();
  acuity_foveation_destroy(planner);
  planner = nullptr;
  acuity_foveation_config_default(&config);
  config.max_rate = 3;
  EXPECT_EQ(acuity_foveation_create(&config, &planner), ACUITY_INVALID_ARGUMENT);
  config.max_rate = 4;
  config.quality = NAN;
  EXPECT_EQ(acuity_foveation_create(&config, &planner), ACUITY_INVALID_ARGUMENT);
  acuity_foveation_config_default(&config);
  ASSERT_EQ(acuity_foveation_create(&config, &planner), ACUITY_OK);
  EXPECT_STREQ(acuity_last_error(), "");

  acuity_eye e = c_eye(640, 480, 40);
  uint32_t cols = 0, rows = 0;
  EXPECT_EQ(acuity_foveation_map_size(&e, 24, &cols, &rows), ACUITY_INVALID_ARGUMENT);
  ASSERT_EQ(acuity_foveation_map_size(&e, 32, &cols, &rows), ACUITY_OK);
  EXPECT_EQ(cols, 20u);
  EXPECT_EQ(rows, 15u);
  std::vector<uint8_t> rate(2 * cols * rows, 0xee);
  std::vector<float> bias(cols * rows, -1);
  // Too small a capacity, a null buffer: nothing written.
  EXPECT_EQ(acuity_foveation_plan(planner, &e, 32, cols * rows - 1, rate.data(), bias.data(), nullptr),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_foveation_plan(planner, &e, 32, cols * rows, nullptr, bias.data(), nullptr),
            ACUITY_INVALID_ARGUMENT);
  EXPECT_EQ(acuity_foveation_plan(nullptr, &e, 32, cols * rows, rate.data(), bias.data(), nullptr),
            ACUITY_INVALID_ARGUMENT);
  for (uint8_t v : rate) ASSERT_EQ(v, 0xee);
  // No gaze, then a NaN eye: written, with the result saying which.
  acuity_foveation_info info;
  e.gaze_valid = 0;
  ASSERT_EQ(acuity_foveation_plan(planner, &e, 32, cols * rows, rate.data(), bias.data(), &info), ACUITY_OK);
  EXPECT_EQ(info.result, uint32_t(ACUITY_FOVEATION_NO_GAZE));
  e.fov_deg[1] = NAN;
  ASSERT_EQ(acuity_foveation_plan(planner, &e, 32, cols * rows, rate.data(), bias.data(), &info), ACUITY_OK);
  EXPECT_EQ(info.result, uint32_t(ACUITY_FOVEATION_INVALID_EYE));
  for (uint8_t v : rate) ASSERT_EQ(v, 1);
  for (float v : bias) ASSERT_EQ(v, 0.0f);
  acuity_guenter_layers layers;
  ASSERT_EQ(acuity_foveation_layers(planner, &e, 3, &layers), ACUITY_OK);
  EXPECT_EQ(layers.n_layers, 0u);
  EXPECT_EQ(acuity_foveation_layers(planner, &e, 9, &layers), ACUITY_INVALID_ARGUMENT);
  acuity_foveation_destroy(planner);
  acuity_foveation_destroy(nullptr);
}
