// The C ABI over acuity::Scheduler: every entry point catches everything.
#include "acuity.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <deque>
#include <iterator>
#include <memory>
#include <new>
#include <string>
#include <type_traits>
#include <unordered_set>
#include <vector>

#include "acuity/blob.hpp"
#include "acuity/foveation_plan.hpp"
#include "acuity/scheduler.hpp"
#include "acuity/version.hpp"

struct acuity_scheduler {
  acuity::Scheduler scheduler;
  std::deque<acuity::Blob> profiles;  // the bytes every Profile points into (stable addresses)
  bool in_frame = false;              // between begin_frame and end_frame
  bool frame_seen = false;            // a frame has begun (the cut reads its eyes)
  std::vector<acuity::View> views;    // [max_views]: the frame's, copied (no allocation per frame)
  explicit acuity_scheduler(const acuity::SchedulerConfig& c) : scheduler(c), views(c.max_views) {}
};

// The C names and layouts are the C++ ones.
static_assert(ACUITY_RULE_PERCEPTUAL == int(acuity::SelectionRule::Perceptual) &&
              ACUITY_RULE_REDDY == int(acuity::SelectionRule::Reddy) &&
              ACUITY_RULE_DISTANCE == int(acuity::SelectionRule::Distance) &&
              ACUITY_RULE_SCREEN_SIZE == int(acuity::SelectionRule::ScreenSize));
static_assert(ACUITY_MODEL_DEFAULT == int(acuity::ThresholdModel::Default) &&
              ACUITY_MODEL_GEISLER_PERRY == int(acuity::ThresholdModel::GeislerPerry) &&
              ACUITY_MODEL_KELLY_DALY == int(acuity::ThresholdModel::KellyDaly) &&
              ACUITY_MODEL_REDDY == int(acuity::ThresholdModel::Reddy) &&
              ACUITY_MODEL_STELA_CSF == int(acuity::ThresholdModel::StelaCsf));
static_assert(ACUITY_VIEW_BLEND_NEAREST == int(acuity::ViewBlend::Nearest) &&
              ACUITY_VIEW_BLEND_MAX3 == int(acuity::ViewBlend::Max3));
static_assert(ACUITY_CSF_DALY1998 == int(acuity::CsfFit::Daly1998) &&
              ACUITY_CSF_LAIRD2006 == int(acuity::CsfFit::Laird2006));
static_assert(int(ACUITY_FLAG_INVALID_INPUT) == int(acuity::kFlagInvalidInput) &&
              int(ACUITY_FLAG_EYE_INSIDE) == int(acuity::kFlagEyeInside) &&
              int(ACUITY_FLAG_NO_GAZE) == int(acuity::kFlagNoGaze) &&
              int(ACUITY_FLAG_BUDGET_FORCED) == int(acuity::kFlagBudgetForced) &&
              int(ACUITY_FLAG_CHANGED) == int(acuity::kFlagChanged) &&
              int(ACUITY_FLAG_HELD) == int(acuity::kFlagHeld));
static_assert(ACUITY_MAX_LEVELS == acuity::kMaxLevels);
static_assert(ACUITY_EVALUATION_TABULATED == int(acuity::Evaluation::Tabulated) &&
              ACUITY_EVALUATION_EXACT == int(acuity::Evaluation::Exact));
static_assert(offsetof(acuity_config, evaluation) == ACUITY_CONFIG_SIZE_V2, "version 3 appends to version 2");
static_assert(offsetof(acuity_config, tabulated_biases) == ACUITY_CONFIG_SIZE_V3,
              "version 4 appends to version 3");
static_assert(std::size(acuity_config{}.tabulated_biases) == acuity::kMaxTabulatedBiases);
static_assert(offsetof(acuity_config, hysteresis_seconds) == ACUITY_CONFIG_SIZE_V4,
              "version 6 appends to version 4");
static_assert(offsetof(acuity_config, max_views) == ACUITY_CONFIG_SIZE_V6, "version 7 appends to version 6");
static_assert(sizeof(acuity_view) == ACUITY_VIEW_SIZE_V7 && sizeof(acuity_view) % 8 == 0,
              "the version-7 view");
static_assert(ACUITY_PROJECTION_PERSPECTIVE == int(acuity::ViewProjection::Perspective) &&
              ACUITY_PROJECTION_ORTHOGRAPHIC == int(acuity::ViewProjection::Orthographic) &&
              ACUITY_VIEW_RULE_FOOTPRINT == int(acuity::ViewRule::Footprint) &&
              ACUITY_VIEW_RULE_AS_EYE == int(acuity::ViewRule::AsEye));
static_assert(sizeof(acuity_config) == ACUITY_CONFIG_SIZE_V7 && sizeof(acuity_config) % 8 == 0,
              "acuity_config grows only by appending fields; then keep ACUITY_CONFIG_SIZE_V2 as the minimum");
static_assert(offsetof(acuity_config, struct_size) == 0);
static_assert(offsetof(acuity_frame_stats, struct_size) == 0 &&
                  sizeof(acuity_frame_stats) == ACUITY_FRAME_STATS_SIZE_V5,
              "the version-5 stats layout");
// The eye and explain structs are copied field by field, so only their field types must agree.
static_assert(sizeof(acuity_eye::position) == sizeof(acuity::Eye::position) &&
              sizeof(acuity_eye::orientation) == sizeof(acuity::Eye::orientation) &&
              sizeof(acuity_eye::fov_deg) == sizeof(acuity::Eye::fov_deg) &&
              sizeof(acuity_eye::viewport) == sizeof(acuity::Eye::viewport) &&
              sizeof(acuity_eye::velocity) == sizeof(acuity::Eye::velocity) &&
              sizeof(acuity_eye::angular_velocity) == sizeof(acuity::Eye::angular_velocity) &&
              sizeof(acuity_eye::gaze_direction) == sizeof(acuity::Gaze::direction) &&
              sizeof(acuity_eye::gaze_angular_velocity) == sizeof(acuity::Gaze::angular_velocity));
static_assert(sizeof(acuity_object_explain::levels) / sizeof(acuity_level_explain) ==
              std::size(acuity::ObjectExplain{}.levels));
static_assert(
    std::is_same_v<decltype(acuity_object_explain::view), decltype(acuity::ObjectExplain::view)> &&
    std::is_same_v<decltype(acuity_object_explain::level), decltype(acuity::ObjectExplain::level)> &&
    std::is_same_v<decltype(acuity_level_explain::band), decltype(acuity::LevelExplain::band)> &&
    std::is_same_v<decltype(acuity_level_explain::score), decltype(acuity::LevelExplain::score)>);

namespace {
thread_local std::string g_error;

acuity_status fail(acuity_status status, std::string message) {
  g_error = std::move(message);
  return status;
}

template <class Fn>
acuity_status guarded(Fn fn) {
  try {
    g_error.clear();
    return fn();
  } catch (const std::bad_alloc&) {
    return fail(ACUITY_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) { return fail(ACUITY_INTERNAL_ERROR, e.what()); } catch (...) {
    return fail(ACUITY_INTERNAL_ERROR, "unknown error");
  }
}

template <class T>
const T* element(const T* base, std::size_t stride, std::size_t i, std::size_t packed) {
  return reinterpret_cast<const T*>(reinterpret_cast<const char*>(base) + i * (stride ? stride : packed));
}

void eye_and_gaze(const acuity_eye& e, acuity::Eye* eye, acuity::Gaze* gaze) {
  std::memcpy(eye->position, e.position, sizeof e.position);
  std::memcpy(eye->orientation, e.orientation, sizeof e.orientation);
  std::memcpy(eye->fov_deg, e.fov_deg, sizeof e.fov_deg);
  std::memcpy(eye->viewport, e.viewport, sizeof e.viewport);
  std::memcpy(eye->velocity, e.velocity, sizeof e.velocity);
  std::memcpy(eye->angular_velocity, e.angular_velocity, sizeof e.angular_velocity);
  std::memcpy(gaze->direction, e.gaze_direction, sizeof e.gaze_direction);
  std::memcpy(gaze->angular_velocity, e.gaze_angular_velocity, sizeof e.gaze_angular_velocity);
  gaze->confidence = e.gaze_confidence;
  gaze->valid = e.gaze_valid != 0;
  gaze->has_velocity = e.gaze_has_velocity != 0;
}

acuity::ObjectTransform transform(const double* p, std::size_t ps, const float* r, std::size_t rs,
                                  const float* s, std::size_t i) {
  acuity::ObjectTransform t;
  const double* pi = element(p, ps, i, 3 * sizeof(double));
  const float* ri = element(r, rs, i, 4 * sizeof(float));
  for (int k = 0; k < 3; ++k) t.position[k] = pi[k];
  for (int k = 0; k < 4; ++k) t.rotation[k] = ri[k];
  t.scale = s ? s[i] : 1.0f;
  return t;
}
// Every id alive (and, when `distinct`, none given twice): the check before any batch call changes anything.
acuity_status check_ids(const acuity_scheduler* s, uint32_t count, const uint32_t* ids, const char* where,
                        bool distinct = false) {
  std::unordered_set<uint32_t> seen;
  for (uint32_t i = 0; i < count; ++i) {
    if (!s->scheduler.alive(ids[i]))
      return fail(ACUITY_INVALID_ARGUMENT,
                  std::string(where) + ": ids[" + std::to_string(i) + "] = " + std::to_string(ids[i]) +
                      " is not a live object (never added, or removed); nothing was changed");
    if (distinct && !seen.insert(ids[i]).second)
      return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + ": id " + std::to_string(ids[i]) +
                                               " is given twice; nothing was changed");
  }
  return ACUITY_OK;
}

bool finite_positive(float x) { return std::isfinite(x) && x > 0; }

// Profile bytes copied (8-byte aligned, as open_profile reads them) and validated; BAD_PROFILE naming
// `where` otherwise. At least the 32-byte header, at most 4 GiB (profiles are kilobytes to
// megabytes): refuses an unchecked ftell's -1 before (size + 7) / 8 could wrap, and 0 before a memcpy
// to null.
acuity_status copy_profile(const void* data, std::size_t size, acuity::Blob* blob, acuity::Profile* p,
                           const char* where) {
  if (size < 32 || size > std::size_t(UINT32_MAX))
    return fail(ACUITY_BAD_PROFILE,
                std::string(where) + ": size " + std::to_string(size) + " bytes is not a profile's size");
  blob->size = size;
  blob->storage.assign((size + 7) / 8, 0);
  std::memcpy(blob->storage.data(), data, size);
  acuity::ProfileError e;
  if (acuity::open_profile(blob->data(), blob->size, p, &e) != acuity::ProfileStatus::Ok)
    return fail(ACUITY_BAD_PROFILE, std::string(acuity::to_string(e.status)) + ": " + e.message);
  return ACUITY_OK;
}

// The config as this library reads it: defaults, overwritten by the caller's struct_size bytes.
acuity_status read_config(const acuity_config* c, acuity::SchedulerConfig* out) {
  const uint32_t size = c->struct_size;
  if (size < ACUITY_CONFIG_SIZE_V2 || size % 8 != 0 || size > 65536)
    return fail(ACUITY_INVALID_ARGUMENT,
                "acuity_create: struct_size " + std::to_string(size) +
                    " is not sizeof(acuity_config) (call acuity_config_default first)");
  acuity_config k;
  (acuity_config_default)(&k);
  std::memcpy(&k, c, std::min<std::size_t>(size, sizeof k));
  const struct {
    const char* name;
    uint32_t value, largest;
  } enums[] = {{"rule", k.rule, ACUITY_RULE_SCREEN_SIZE},
               {"model", k.model, ACUITY_MODEL_STELA_CSF},
               {"view_blend", k.view_blend, ACUITY_VIEW_BLEND_MAX3},
               {"params.csf_fit", k.params.csf_fit, ACUITY_CSF_LAIRD2006},
               {"evaluation", k.evaluation, ACUITY_EVALUATION_EXACT}};
  for (const auto& e : enums)
    if (e.value > e.largest)
      return fail(ACUITY_INVALID_ARGUMENT, std::string("acuity_create: bad ") + e.name + " " +
                                               std::to_string(e.value) + " (0.." + std::to_string(e.largest) +
                                               ")");
  if (k.max_objects == 0 || k.reserved != 0 || k.params.reserved != 0 || k.reserved3 != 0 || k.reserved4 != 0)
    return fail(ACUITY_INVALID_ARGUMENT, "acuity_create: max_objects 0 or a reserved field not 0");
  if (!finite_positive(k.quality) || k.fallback_level >= ACUITY_MAX_LEVELS)
    return fail(ACUITY_INVALID_ARGUMENT, "acuity_create: quality or fallback_level out of range");
  const struct {
    const char* name;
    float value;
  } durations[] = {{"transition_seconds", k.transition_seconds},
                   {"hysteresis_seconds", k.hysteresis_seconds},
                   {"max_coarsen_wait_seconds", k.max_coarsen_wait_seconds}};
  for (const auto& d : durations)
    if (!std::isfinite(d.value) || d.value < 0)
      return fail(ACUITY_INVALID_ARGUMENT, std::string("acuity_create: ") + d.name + " " +
                                               std::to_string(d.value) + " is negative or not finite");
  if (k.max_views > 1024 || k.max_view_classes > 256)
    return fail(ACUITY_INVALID_ARGUMENT, "acuity_create: max_views above 1024 or max_view_classes above 256");
  for (const float b : k.tabulated_biases)
    if (b != 0 && !finite_positive(b))
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_create: a tabulated_biases entry is neither 0 nor finite and > 0");
  acuity::SchedulerConfig& sc = *out;
  sc.max_objects = k.max_objects;
  sc.max_profiles = k.max_profiles;
  sc.rule = static_cast<acuity::SelectionRule>(k.rule);
  sc.evaluation = static_cast<acuity::Evaluation>(k.evaluation);
  sc.model = static_cast<acuity::ThresholdModel>(k.model);
  sc.view_blend = static_cast<acuity::ViewBlend>(k.view_blend);
  sc.quality = k.quality;
  sc.fallback_level = static_cast<std::uint8_t>(k.fallback_level);
  sc.min_gaze_confidence = k.min_gaze_confidence;
  sc.gaze_uncertainty_deg = k.gaze_uncertainty_deg;
  sc.no_gaze_radius_deg = k.no_gaze_radius_deg;
  sc.hysteresis_margin = k.hysteresis_margin;
  sc.hysteresis_frames = k.hysteresis_frames;
  sc.hysteresis_seconds = k.hysteresis_seconds;
  sc.max_coarsen_wait_seconds = k.max_coarsen_wait_seconds;
  sc.saccade_speed = k.saccade_speed_deg_s;
  sc.max_coarsen_wait = k.max_coarsen_wait;
  sc.transition_seconds = k.transition_seconds;
  sc.triangle_budget = k.triangle_budget;
  sc.distance_scale = k.distance_scale;
  sc.pixel_error = k.pixel_error;
  sc.keep_scores = k.keep_scores != 0;
  sc.max_views = k.max_views;
  sc.max_view_classes = k.max_view_classes;
  std::copy(std::begin(k.tabulated_biases), std::end(k.tabulated_biases), sc.tabulated_biases);
  const acuity_model_params& p = k.params;
  sc.params.ct0 = p.ct0;
  sc.params.alpha = p.alpha;
  sc.params.e2 = p.e2;
  sc.params.pursuit_gain = p.pursuit_gain;
  sc.params.pursuit_min = p.pursuit_min;
  sc.params.pursuit_max = p.pursuit_max;
  sc.params.drift = p.drift;
  sc.params.reddy_contrast = p.reddy_contrast;
  sc.params.fit = static_cast<acuity::CsfFit>(p.csf_fit);
  return ACUITY_OK;
}
}  // namespace

extern "C" {

uint32_t acuity_version(void) { return ACUITY_VERSION; }
const char* acuity_last_error(void) { return g_error.c_str(); }

namespace {
// Writes `full` (the library's whole struct of full_size bytes) over the caller's first `size` bytes,
// zeros past it, struct_size (the first field) = size: the caller's struct is never written past.
void write_defaults(const void* full, std::size_t full_size, void* out, std::size_t size) {
  unsigned char* bytes = static_cast<unsigned char*>(out);
  std::memcpy(bytes, full, std::min(size, full_size));
  if (size > full_size) std::memset(bytes + full_size, 0, size - full_size);
  const auto size32 = static_cast<uint32_t>(size);
  std::memcpy(bytes, &size32, sizeof size32);
}
bool default_size_ok(std::size_t size, std::size_t least, std::size_t multiple) {
  return size >= least && size % multiple == 0 && size <= 65536;
}
}  // namespace

void acuity_config_default_sized(acuity_config* c, size_t size) {
  if (!c || !default_size_ok(size, ACUITY_CONFIG_SIZE_V2, 8)) return;
  acuity_config full;
  (acuity_config_default)(&full);
  write_defaults(&full, sizeof full, c, size);
}

void(acuity_config_default)(acuity_config* c) {
  if (!c) return;
  const acuity::SchedulerConfig d;
  std::memset(c, 0, sizeof *c);
  c->struct_size = sizeof *c;
  c->max_objects = d.max_objects;
  c->max_profiles = d.max_profiles;
  c->rule = static_cast<uint32_t>(d.rule);
  c->evaluation = static_cast<uint32_t>(d.evaluation);
  c->model = static_cast<uint32_t>(d.model);
  c->view_blend = static_cast<uint32_t>(d.view_blend);
  c->quality = d.quality;
  c->fallback_level = d.fallback_level;
  c->min_gaze_confidence = d.min_gaze_confidence;
  c->gaze_uncertainty_deg = d.gaze_uncertainty_deg;
  c->no_gaze_radius_deg = d.no_gaze_radius_deg;
  c->hysteresis_margin = d.hysteresis_margin;
  c->hysteresis_frames = d.hysteresis_frames;
  c->hysteresis_seconds = d.hysteresis_seconds;
  c->max_coarsen_wait_seconds = d.max_coarsen_wait_seconds;
  c->saccade_speed_deg_s = d.saccade_speed;
  c->max_coarsen_wait = d.max_coarsen_wait;
  c->transition_seconds = d.transition_seconds;
  c->triangle_budget = d.triangle_budget;
  c->distance_scale = d.distance_scale;
  c->pixel_error = d.pixel_error;
  c->keep_scores = d.keep_scores ? 1u : 0u;
  c->max_views = d.max_views;
  c->max_view_classes = d.max_view_classes;
  std::copy(std::begin(d.tabulated_biases), std::end(d.tabulated_biases), c->tabulated_biases);
  c->params.ct0 = d.params.ct0;
  c->params.alpha = d.params.alpha;
  c->params.e2 = d.params.e2;
  c->params.pursuit_gain = d.params.pursuit_gain;
  c->params.pursuit_min = d.params.pursuit_min;
  c->params.pursuit_max = d.params.pursuit_max;
  c->params.drift = d.params.drift;
  c->params.reddy_contrast = d.params.reddy_contrast;
  c->params.csf_fit = static_cast<uint32_t>(d.params.fit);
}

void acuity_eye_default(acuity_eye* e) {
  if (!e) return;
  const acuity::Eye d;
  const acuity::Gaze g;
  std::memset(e, 0, sizeof *e);
  std::memcpy(e->position, d.position, sizeof e->position);
  std::memcpy(e->orientation, d.orientation, sizeof e->orientation);
  std::memcpy(e->fov_deg, d.fov_deg, sizeof e->fov_deg);
  std::memcpy(e->viewport, d.viewport, sizeof e->viewport);
  std::memcpy(e->gaze_direction, g.direction, sizeof e->gaze_direction);
  e->gaze_confidence = g.confidence;
}

acuity_status acuity_create(const acuity_config* c, acuity_scheduler** out) {
  return guarded([&] {
    if (!c || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_create: null argument");
    acuity::SchedulerConfig sc;
    if (const acuity_status st = read_config(c, &sc); st != ACUITY_OK) return st;
    *out = new acuity_scheduler(sc);
    return ACUITY_OK;
  });
}

void acuity_destroy(acuity_scheduler* s) { delete s; }

namespace {
// acuity_load_profile and _deferred (`name`): the bytes validated and copied, the profile added.
acuity_status load_profile(acuity_scheduler* s, const void* data, size_t size, int32_t* index, bool deferred,
                           const std::string& name) {
  return guarded([&] {
    if (!s || !data || !index) return fail(ACUITY_INVALID_ARGUMENT, name + ": null argument");
    if (s->profiles.size() >= s->scheduler.config().max_profiles)
      return fail(ACUITY_FULL, name + ": max_profiles (" +
                                   std::to_string(s->scheduler.config().max_profiles) + ") reached");
    acuity::Blob blob;
    acuity::Profile p;
    if (const acuity_status st = copy_profile(data, size, &blob, &p, name.c_str()); st != ACUITY_OK)
      return st;
    s->profiles.push_back(std::move(blob));
    acuity::open_profile(s->profiles.back().data(), s->profiles.back().size, &p);  // point into the kept copy
    const int i = deferred ? s->scheduler.add_profile_deferred(p) : s->scheduler.add_profile(p);
    if (i < 0) {
      s->profiles.pop_back();
      return fail(ACUITY_FULL, name + ": max_profiles reached");
    }
    *index = i;
    return ACUITY_OK;
  });
}
}  // namespace

acuity_status acuity_load_profile(acuity_scheduler* s, const void* data, size_t size, int32_t* index) {
  return load_profile(s, data, size, index, false, "acuity_load_profile");
}

acuity_status acuity_load_profile_deferred(acuity_scheduler* s, const void* data, size_t size,
                                           int32_t* index) {
  return load_profile(s, data, size, index, true, "acuity_load_profile_deferred");
}

struct acuity_tables {
  acuity::ProfileTables tables;
};

namespace {
// acuity_make_tables and _view_tables (`name`): view acuity::Scheduler::kAllViews or one.
acuity_status make_tables(const acuity_scheduler* s, int32_t profile, int view, acuity_tables** out,
                          const char* name) {
  return guarded([&] {
    if (!s || !out) return fail(ACUITY_INVALID_ARGUMENT, std::string(name) + ": null argument");
    acuity::ProfileTables t = s->scheduler.make_tables(profile, view);
    if (!t)
      return fail(ACUITY_INVALID_ARGUMENT,
                  std::string(name) + ": profile " + std::to_string(profile) +
                      (view == acuity::Scheduler::kAllViews ? "" : " view " + std::to_string(view)) +
                      " was not loaded, or this scheduler keeps no tables");
    *out = new acuity_tables{std::move(t)};
    return ACUITY_OK;
  });
}
}  // namespace

acuity_status acuity_make_tables(const acuity_scheduler* s, int32_t profile, acuity_tables** out) {
  return make_tables(s, profile, acuity::Scheduler::kAllViews, out, "acuity_make_tables");
}

acuity_status acuity_make_view_tables(const acuity_scheduler* s, int32_t profile, uint32_t view,
                                      acuity_tables** out) {
  const int v = view > uint32_t(INT32_MAX) ? INT32_MAX : static_cast<int>(view);  // out of range either way
  return make_tables(s, profile, v, out, "acuity_make_view_tables");
}

acuity_status acuity_wanted_tables(acuity_scheduler* s, int32_t* profiles, uint32_t* views, uint32_t capacity,
                                   uint32_t* count) {
  return guarded([&] {
    if (!s || !count || (capacity > 0 && (!profiles || !views)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_wanted_tables: null argument");
    if (s->in_frame)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_wanted_tables: called between begin_frame and end_frame");
    acuity::TablesWanted wanted[64];
    uint32_t n = 0;
    while (n < capacity) {
      const uint32_t got =
          s->scheduler.wanted_tables(std::span(wanted, std::min<uint32_t>(64, capacity - n)));
      for (uint32_t i = 0; i < got; ++i, ++n) {
        profiles[n] = wanted[i].profile;
        views[n] = wanted[i].view;
      }
      if (got == 0) break;
    }
    *count = n;
    return ACUITY_OK;
  });
}

acuity_status acuity_install_tables(acuity_scheduler* s, int32_t profile, acuity_tables* tables) {
  return guarded([&] {
    if (!s || !tables) return fail(ACUITY_INVALID_ARGUMENT, "acuity_install_tables: null argument");
    if (s->in_frame)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_install_tables: called between begin_frame and end_frame");
    if (!s->scheduler.install_tables(profile, std::move(tables->tables)))
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_install_tables: tables made for another profile or scheduler, "
                  "or profile " +
                      std::to_string(profile) + " has tables of their views");
    delete tables;
    return ACUITY_OK;
  });
}

acuity_status acuity_drop_idle_tables(acuity_scheduler* s, uint32_t frames, size_t* freed) {
  return guarded([&] {
    if (!s) return fail(ACUITY_INVALID_ARGUMENT, "acuity_drop_idle_tables: null scheduler");
    if (s->in_frame)
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_drop_idle_tables: called between begin_frame and end_frame");
    const std::size_t bytes = s->scheduler.drop_idle_tables(frames);
    if (freed) *freed = bytes;
    return ACUITY_OK;
  });
}

void acuity_tables_destroy(acuity_tables* tables) { delete tables; }

acuity_status acuity_add_objects(acuity_scheduler* s, uint32_t count, const int32_t* profiles,
                                 const double* positions, size_t ps, const float* rotations, size_t rs,
                                 const float* scales, uint32_t* ids) {
  return guarded([&] {
    if (!s || (count && (!profiles || !positions || !rotations || !ids)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_add_objects: null argument");
    for (uint32_t i = 0; i < count; ++i)
      if (profiles[i] < 0 || std::size_t(profiles[i]) >= s->profiles.size())
        return fail(ACUITY_INVALID_ARGUMENT,
                    "acuity_add_objects: profiles[" + std::to_string(i) +
                        "] = " + std::to_string(profiles[i]) + " is not a loaded profile (" +
                        std::to_string(s->profiles.size()) + " loaded); nothing was added");
    std::vector<uint32_t> added;
    added.reserve(count);
    for (uint32_t i = 0; i < count; ++i) {
      const uint32_t id =
          s->scheduler.add_object(profiles[i], transform(positions, ps, rotations, rs, scales, i));
      if (id == acuity::kInvalidObject) {
        for (auto it = added.rbegin(); it != added.rend(); ++it)
          s->scheduler.remove_object(*it);  // all or nothing
        return fail(ACUITY_FULL, "acuity_add_objects: max_objects reached at object " + std::to_string(i));
      }
      added.push_back(id);
    }
    std::copy(added.begin(), added.end(), ids);
    return ACUITY_OK;
  });
}

acuity_status acuity_remove_objects(acuity_scheduler* s, uint32_t count, const uint32_t* ids) {
  return guarded([&] {
    if (!s || (count && !ids)) return fail(ACUITY_INVALID_ARGUMENT, "acuity_remove_objects: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_remove_objects", true); st != ACUITY_OK)
      return st;
    for (uint32_t i = 0; i < count; ++i) s->scheduler.remove_object(ids[i]);
    return ACUITY_OK;
  });
}

acuity_status acuity_set_transforms(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                    const double* positions, size_t ps, const float* rotations, size_t rs,
                                    const float* scales) {
  return guarded([&] {
    if (!s || (count && (!ids || !positions || !rotations)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_transforms: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_set_transforms"); st != ACUITY_OK)
      return st;
    for (uint32_t i = 0; i < count; ++i)
      s->scheduler.set_transform(ids[i], transform(positions, ps, rotations, rs, scales, i));
    return ACUITY_OK;
  });
}

acuity_status acuity_set_velocities(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const float* v,
                                    size_t vs) {
  return guarded([&] {
    if (!s || (count && (!ids || !v)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_velocities: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_set_velocities"); st != ACUITY_OK)
      return st;
    for (uint32_t i = 0; i < count; ++i)
      s->scheduler.set_velocity(ids[i], element(v, vs, i, 3 * sizeof(float)));
    return ACUITY_OK;
  });
}

acuity_status acuity_set_bias(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const float* biases) {
  return guarded([&] {
    if (!s || (count && (!ids || !biases)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_bias: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_set_bias"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i)
      if (!finite_positive(biases[i]))
        return fail(ACUITY_INVALID_ARGUMENT,
                    "acuity_set_bias: bias " + std::to_string(i) + " is not finite and > 0");
    for (uint32_t i = 0; i < count; ++i) s->scheduler.set_bias(ids[i], biases[i]);
    return ACUITY_OK;
  });
}

acuity_status acuity_set_clamps(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const uint8_t* lo,
                                const uint8_t* hi) {
  return guarded([&] {
    if (!s || (count && (!ids || !lo || !hi)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_clamps: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_set_clamps"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i)
      if (hi[i] < lo[i])
        return fail(ACUITY_INVALID_ARGUMENT,
                    "acuity_set_clamps: clamp " + std::to_string(i) + ": max_level < min_level");
    for (uint32_t i = 0; i < count; ++i) s->scheduler.set_clamps(ids[i], lo[i], hi[i]);
    return ACUITY_OK;
  });
}

namespace {
// acuity_begin_frame and acuity_begin_frame_views: every check first, then the frame.
acuity_status begin(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count, float dt,
                    const acuity_view* views, uint32_t view_count, size_t view_size, const char* name) {
  const auto where = [name] { return std::string(name); };  // built only for a message
  if (!s || !eyes || eye_count < 1 || eye_count > 2)
    return fail(ACUITY_INVALID_ARGUMENT, where() + ": one or two eyes");
  if (s->in_frame) return fail(ACUITY_INVALID_ARGUMENT, where() + ": the previous frame was not ended");
  const acuity::SchedulerConfig& config = s->scheduler.config();
  if (view_count > 0 && !views) return fail(ACUITY_INVALID_ARGUMENT, where() + ": null views");
  if (view_count > config.max_views)
    return fail(ACUITY_INVALID_ARGUMENT, where() + ": " + std::to_string(view_count) +
                                             " views, more than max_views " +
                                             std::to_string(config.max_views));
  if (view_count > 0 && (view_size < ACUITY_VIEW_SIZE_V7 || view_size % 8 != 0 || view_size > 65536))
    return fail(ACUITY_INVALID_ARGUMENT,
                where() + ": view_size " + std::to_string(view_size) + " is not sizeof(acuity_view)");
  for (uint32_t i = 0; i < view_count; ++i) {
    const acuity_view& v = *element(views, view_size, i, sizeof(acuity_view));
    if (v.view_class >= config.max_view_classes || v.projection > ACUITY_PROJECTION_ORTHOGRAPHIC ||
        v.rule > ACUITY_VIEW_RULE_AS_EYE)
      return fail(ACUITY_INVALID_ARGUMENT, where() + ": views[" + std::to_string(i) +
                                               "] has a view_class not below max_view_classes (" +
                                               std::to_string(config.max_view_classes) +
                                               ") or an unknown projection or rule; nothing was begun");
  }
  acuity::Frame f;
  f.eye_count = eye_count;
  f.dt = dt;
  for (uint32_t i = 0; i < eye_count; ++i) eye_and_gaze(eyes[i], &f.eyes[i], &f.gaze[i]);
  for (uint32_t i = 0; i < view_count; ++i) {
    const acuity_view& v = *element(views, view_size, i, sizeof(acuity_view));
    acuity::View& to = s->views[i];
    to.view_class = v.view_class;
    to.projection = static_cast<acuity::ViewProjection>(v.projection);
    to.rule = static_cast<acuity::ViewRule>(v.rule);
    to.pixel_error = v.pixel_error;
    std::memcpy(to.position, v.position, sizeof v.position);
    std::memcpy(to.orientation, v.orientation, sizeof v.orientation);
    std::memcpy(to.fov_deg, v.fov_deg, sizeof v.fov_deg);
    std::memcpy(to.extent_m, v.extent_m, sizeof v.extent_m);
    std::memcpy(to.viewport, v.viewport, sizeof v.viewport);
  }
  f.views = s->views.data();
  f.view_count = view_count;
  s->scheduler.begin_frame(f);
  s->in_frame = true;
  s->frame_seen = true;
  return ACUITY_OK;
}
}  // namespace

acuity_status acuity_begin_frame(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count, float dt) {
  return guarded([&] { return begin(s, eyes, eye_count, dt, nullptr, 0, 0, "acuity_begin_frame"); });
}

acuity_status acuity_begin_frame_views(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count,
                                       float dt, const acuity_view* views, uint32_t view_count,
                                       size_t view_size) {
  return guarded([&] {
    return begin(s, eyes, eye_count, dt, views, view_count, view_size, "acuity_begin_frame_views");
  });
}

acuity_status acuity_update_range(acuity_scheduler* s, uint32_t first, uint32_t count) {
  return guarded([&] {
    if (!s) return fail(ACUITY_INVALID_ARGUMENT, "acuity_update_range: null scheduler");
    if (!s->in_frame)
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_update_range: no frame begun (call acuity_begin_frame first); nothing was updated");
    const uint32_t capacity = s->scheduler.object_capacity();
    if (first >= capacity) return ACUITY_OK;
    count = std::min(count, capacity - first);
    s->scheduler.update(first, count);
    return ACUITY_OK;
  });
}

acuity_status acuity_end_frame(acuity_scheduler* s) {
  return guarded([&] {
    if (!s) return fail(ACUITY_INVALID_ARGUMENT, "acuity_end_frame: null scheduler");
    if (!s->in_frame)
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_end_frame: no frame begun (call acuity_begin_frame first)");
    s->scheduler.end_frame();
    s->in_frame = false;
    return ACUITY_OK;
  });
}

acuity_status acuity_get_levels(const acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                uint8_t* levels, uint8_t* flags) {
  return guarded([&] {
    if (!s || (count && (!ids || !levels)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_levels: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_get_levels"); st != ACUITY_OK) return st;
    const uint8_t *level = s->scheduler.level_array(), *flag = s->scheduler.flag_array();
    for (uint32_t i = 0; i < count; ++i) {
      levels[i] = level[ids[i]];
      if (flags) flags[i] = flag[ids[i]];
    }
    return ACUITY_OK;
  });
}

acuity_status acuity_get_view_levels(const acuity_scheduler* s, uint32_t view_class, uint32_t count,
                                     const uint32_t* ids, uint8_t* levels) {
  return guarded([&] {
    if (!s || (count && (!ids || !levels)))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_view_levels: null argument");
    const uint8_t* level = s->scheduler.view_level_array(view_class);
    if (!level)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_view_levels: view_class " +
                                               std::to_string(view_class) + " is not below max_view_classes");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_get_view_levels"); st != ACUITY_OK)
      return st;
    for (uint32_t i = 0; i < count; ++i) levels[i] = level[ids[i]];
    return ACUITY_OK;
  });
}

acuity_status acuity_get_transitions(const acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                     uint8_t* previous, float* fades) {
  return guarded([&] {
    if (!s || (count && !ids)) return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_transitions: null argument");
    if (const acuity_status st = check_ids(s, count, ids, "acuity_get_transitions"); st != ACUITY_OK)
      return st;
    const uint8_t* previous_level = s->scheduler.previous_level_array();
    const float* fade = s->scheduler.transition_array();
    for (uint32_t i = 0; i < count; ++i) {
      if (previous) previous[i] = previous_level[ids[i]];
      if (fades) fades[i] = fade[ids[i]];
    }
    return ACUITY_OK;
  });
}

acuity_status acuity_explain(const acuity_scheduler* s, uint32_t id, acuity_object_explain* out) {
  return guarded([&] {
    if (!s || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_explain: null argument");
    acuity::ObjectExplain e;
    if (!s->scheduler.alive(id) || !s->scheduler.explain(id, &e))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_explain: no object " + std::to_string(id));
    acuity_object_explain r;
    std::memset(&r, 0, sizeof r);
    r.distance_m = e.distance_m;
    r.angular_diameter_deg = e.angular_diameter_deg;
    r.eccentricity_deg = e.eccentricity_deg;
    r.image_velocity_deg_s = e.image_velocity_deg_s;
    r.retinal_velocity_deg_s = e.retinal_velocity_deg_s;
    r.view = e.view;
    r.level = e.level;
    r.level_count = e.level_count;
    for (std::size_t k = 0; k < std::size(e.levels) && k < e.level_count; ++k) {
      r.levels[k].score = e.levels[k].score;
      r.levels[k].band = e.levels[k].band;
      r.levels[k].orientation = e.levels[k].orientation;
      r.levels[k].frequency_cpd = e.levels[k].frequency_cpd;
      r.levels[k].threshold = e.levels[k].threshold;
    }
    *out = r;
    return ACUITY_OK;
  });
}

uint64_t acuity_frame_triangles(const acuity_scheduler* s) { return s ? s->scheduler.stats().triangles : 0; }

acuity_status acuity_get_frame_stats(const acuity_scheduler* s, acuity_frame_stats* out) {
  return guarded([&] {
    if (!s || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_frame_stats: null argument");
    const uint32_t size = out->struct_size;
    if (size < ACUITY_FRAME_STATS_SIZE_V5 || size % 8 != 0 || size > 65536)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_frame_stats: struct_size " + std::to_string(size) +
                                               " (at least " + std::to_string(ACUITY_FRAME_STATS_SIZE_V5) +
                                               ", a multiple of 8, at most 65536)");
    const acuity::FrameStats& st = s->scheduler.stats();
    acuity_frame_stats r;
    std::memset(&r, 0, sizeof r);
    r.struct_size = size;
    r.changed = st.changed;
    r.triangles = st.triangles;
    r.budget_forced = st.budget_forced;
    r.invalid = st.invalid;
    r.at_rest = st.at_rest;
    r.gaze_used = st.gaze_used ? 1 : 0;
    std::memcpy(out, &r, std::min<std::size_t>(size, sizeof r));
    return ACUITY_OK;
  });
}

}  // extern "C"

// ---- Cluster cuts ----------------------------------------------------------------------------------

// A hierarchy's records and loss, copied and checked (acuity::check_cluster_records).
struct acuity_hierarchy {
  std::vector<acuity::Cluster> clusters;
  std::vector<acuity::ClusterGroup> groups;
  std::vector<std::uint32_t> roots, made;  // acuity::cluster_roots, cluster_made_index
  std::vector<float> bands, lost;
  std::vector<float> view_directions, view_lost;  // the loss per view cell, or empty
  std::vector<float> ln_lost, ln_view_lost;       // their logs (acuity::loss_logs)
  float diameter = 0;
  acuity::ClusterView view() const { return {clusters, groups, roots, made}; }
  acuity::ClusterLoss loss() const {
    return {bands, diameter, lost, view_directions, view_lost, ln_lost, ln_view_lost};
  }
};
static_assert(sizeof(acuity_cluster) == sizeof(acuity::Cluster) &&
                  offsetof(acuity_cluster, refined) == offsetof(acuity::Cluster, refined) &&
                  sizeof(acuity_cluster_group) == sizeof(acuity::ClusterGroup) &&
                  offsetof(acuity_cluster_group, error) == offsetof(acuity::ClusterGroup, error) &&
                  offsetof(acuity_cluster_group, level) == offsetof(acuity::ClusterGroup, level) &&
                  ACUITY_NO_GROUP == acuity::kNoGroup,
              "the C records are the C++ ones");
static_assert(sizeof(acuity_cut_result) == ACUITY_CUT_RESULT_SIZE_V9 &&
                  offsetof(acuity_cut_result, budget_coarsened) == ACUITY_CUT_RESULT_SIZE_V8 &&
                  offsetof(acuity_cut_result, struct_size) == 0,
              "the version-9 cut result: version 8's, then the budget's fields");
static_assert(ACUITY_CUT_OK == int(acuity::CutStatus::Ok) &&
              ACUITY_CUT_INVALID_INPUT == int(acuity::CutStatus::InvalidInput));

namespace {
// One object's cut memory: per group what the cut remembers, then the budget's candidates
// (4-byte aligned after the memory's 12 bytes per group), then the walk's scratch byte.
constexpr std::size_t kCutBytesPerGroup = sizeof(acuity::CutGroupMemory) + sizeof(acuity::CutCandidate) + 1;
static_assert(sizeof(acuity::CutGroupMemory) % alignof(acuity::CutCandidate) == 0);

// The checks and copies of both acuity_hierarchy_create calls (lost: groups x bands, already copied).
acuity_status make_hierarchy(const acuity_cluster* clusters, uint32_t cluster_count,
                             const acuity_cluster_group* groups, uint32_t group_count,
                             const float* bands_cpod, uint32_t band_count, float diameter,
                             const std::vector<float>& lost, acuity_hierarchy** out, const char* where) {
  if (cluster_count == 0) return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + "no cluster");
  if (band_count == 0 || band_count > acuity::kMaxBands)
    return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + std::to_string(band_count) +
                                             " bands, not 1 .. " + std::to_string(acuity::kMaxBands));
  if (!finite_positive(diameter))
    return fail(ACUITY_INVALID_ARGUMENT,
                std::string(where) + "diameter " + std::to_string(diameter) + " is not finite and > 0");
  for (uint32_t b = 0; b < band_count; ++b)
    if (!finite_positive(bands_cpod[b]) || (b > 0 && !(bands_cpod[b] > bands_cpod[b - 1])))
      return fail(ACUITY_INVALID_ARGUMENT,
                  std::string(where) + "band " + std::to_string(b) + " is not finite, > 0 and increasing");
  auto h = std::make_unique<acuity_hierarchy>();
  h->clusters.resize(cluster_count);
  std::memcpy(static_cast<void*>(h->clusters.data()), clusters, sizeof(acuity_cluster) * cluster_count);
  h->groups.resize(group_count);
  if (group_count)
    std::memcpy(static_cast<void*>(h->groups.data()), groups, sizeof(acuity_cluster_group) * group_count);
  std::uint64_t triangles = 0;
  for (const acuity::Cluster& c : h->clusters) triangles += c.triangle_count;
  if (const std::string fault = acuity::check_cluster_records(h->clusters, h->groups, triangles);
      !fault.empty())
    return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + fault);
  h->roots = acuity::cluster_roots(h->clusters);
  h->made = acuity::cluster_made_index(h->clusters, h->groups.size());
  h->bands.assign(bands_cpod, bands_cpod + band_count);
  h->lost = lost;
  h->ln_lost = acuity::loss_logs(lost);
  h->diameter = diameter;
  *out = h.release();
  return ACUITY_OK;
}
}  // namespace

extern "C" {

acuity_status acuity_hierarchy_create(const acuity_cluster* clusters, uint32_t cluster_count,
                                      const acuity_cluster_group* groups, uint32_t group_count,
                                      const float* bands_cpod, uint32_t band_count, float diameter,
                                      const float* lost, acuity_hierarchy** out) {
  return guarded([&] {
    const char* where = "acuity_hierarchy_create: ";
    if (!clusters || !bands_cpod || !out || (group_count > 0 && (!groups || !lost)))
      return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + "null argument");
    const std::vector<float> copy(lost, lost + std::size_t(group_count) * band_count);
    return make_hierarchy(clusters, cluster_count, groups, group_count, bands_cpod, band_count, diameter,
                          copy, out, where);
  });
}

acuity_status acuity_hierarchy_create_from_profile(const acuity_cluster* clusters, uint32_t cluster_count,
                                                   const acuity_cluster_group* groups, uint32_t group_count,
                                                   const void* profile, size_t profile_size,
                                                   acuity_hierarchy** out) {
  return guarded([&] {
    const char* where = "acuity_hierarchy_create_from_profile: ";
    if (!clusters || !profile || !out || (group_count > 0 && !groups))
      return fail(ACUITY_INVALID_ARGUMENT, std::string(where) + "null argument");
    acuity::Blob blob;
    acuity::Profile p{};
    if (const acuity_status st =
            copy_profile(profile, profile_size, &blob, &p, "acuity_hierarchy_create_from_profile");
        st != ACUITY_OK)
      return st;
    std::vector<acuity::ClusterGroup> records(group_count);
    if (group_count)
      std::memcpy(static_cast<void*>(records.data()), groups, sizeof(acuity_cluster_group) * group_count);
    std::vector<acuity::Cluster> cluster_records(cluster_count);
    std::memcpy(static_cast<void*>(cluster_records.data()), clusters, sizeof(acuity_cluster) * cluster_count);
    // The measured loss (the profile's Clusters section, and its cells when it has them), else the
    // provisional one derived from a chain profile.
    acuity::ClusterLoss loss;
    std::vector<float> lost;
    switch (acuity::measured_group_loss(p, cluster_records, records, &loss)) {
      case acuity::GroupLossStatus::Measured:
        lost.assign(loss.lost.begin(), loss.lost.end());
        break;
      case acuity::GroupLossStatus::NoSection:
        lost = acuity::provisional_group_loss(p, records, &loss);
        break;
      case acuity::GroupLossStatus::OtherHierarchy:
        return fail(ACUITY_BAD_PROFILE,
                    std::string(where) + to_string(acuity::GroupLossStatus::OtherHierarchy));
    }
    const acuity_status st =
        make_hierarchy(clusters, cluster_count, groups, group_count, loss.bands_cpod.data(),
                       uint32_t(loss.bands_cpod.size()), loss.diameter, lost, out, where);
    if (st == ACUITY_OK) {
      (*out)->view_directions.assign(loss.view_directions.begin(), loss.view_directions.end());
      (*out)->view_lost.assign(loss.view_lost.begin(), loss.view_lost.end());
      (*out)->ln_view_lost = acuity::loss_logs(loss.view_lost);
    }
    return st;
  });
}

void acuity_hierarchy_destroy(acuity_hierarchy* h) { delete h; }

size_t acuity_cut_memory_size(const acuity_hierarchy* h) {
  return h ? std::max<std::size_t>(h->groups.size() * kCutBytesPerGroup, 1) : 0;
}

acuity_status acuity_select_cut(const acuity_scheduler* s, const acuity_hierarchy* h,
                                const double position[3], const float rotation[4], float scale,
                                const float* velocity, void* memory, size_t memory_size, uint32_t capacity,
                                uint32_t* drawn, acuity_cut_result* result) {
  return acuity_select_cut_budget(s, h, position, rotation, scale, velocity, 0, memory, memory_size, capacity,
                                  drawn, result);
}

acuity_status acuity_select_cut_budget(const acuity_scheduler* s, const acuity_hierarchy* h,
                                       const double position[3], const float rotation[4], float scale,
                                       const float* velocity, uint64_t triangle_budget, void* memory,
                                       size_t memory_size, uint32_t capacity, uint32_t* drawn,
                                       acuity_cut_result* result) {
  return guarded([&] {
    const std::string where = triangle_budget ? "acuity_select_cut_budget: " : "acuity_select_cut: ";
    if (!s || !h || !position || !rotation || !memory || !drawn || !result)
      return fail(ACUITY_INVALID_ARGUMENT, where + "null argument");
    const uint32_t size = result->struct_size;
    if (size < ACUITY_CUT_RESULT_SIZE_V8 || size % 8 != 0 || size > 65536)
      return fail(ACUITY_INVALID_ARGUMENT, where + "result struct_size " + std::to_string(size) +
                                               " (at least " + std::to_string(ACUITY_CUT_RESULT_SIZE_V8) +
                                               ", a multiple of 8, at most 65536)");
    const std::size_t G = h->groups.size();
    if (memory_size < acuity_cut_memory_size(h) || reinterpret_cast<std::uintptr_t>(memory) % 4 != 0)
      return fail(ACUITY_INVALID_ARGUMENT,
                  where + "memory of " + std::to_string(memory_size) +
                      " bytes (needs acuity_cut_memory_size: " + std::to_string(acuity_cut_memory_size(h)) +
                      ", 4-byte aligned)");
    if (capacity < h->clusters.size())
      return fail(ACUITY_INVALID_ARGUMENT, where + "capacity " + std::to_string(capacity) +
                                               " is below the hierarchy's " +
                                               std::to_string(h->clusters.size()) + " clusters");
    if (!s->frame_seen) return fail(ACUITY_INVALID_ARGUMENT, where + "no frame begun yet");
    acuity::ObjectTransform t;
    for (int k = 0; k < 3; ++k) t.position[k] = position[k];
    for (int k = 0; k < 4; ++k) t.rotation[k] = rotation[k];
    t.scale = scale;
    auto* remembered = static_cast<acuity::CutGroupMemory*>(memory);
    auto* candidates = reinterpret_cast<acuity::CutCandidate*>(remembered + G);
    auto* scratch = reinterpret_cast<std::uint8_t*>(candidates + G);
    const acuity::CutBudget budget{triangle_budget, {candidates, G}};
    const acuity::CutResult r = s->scheduler.select_cut(h->view(), h->loss(), t, velocity, {remembered, G},
                                                        budget, {scratch, G}, {drawn, capacity});
    acuity_cut_result out;
    std::memset(&out, 0, sizeof out);
    out.struct_size = size;
    out.status = uint32_t(r.status);
    out.flags = r.flags;
    out.clusters = r.clusters;
    out.triangles = r.triangles;
    out.groups_evaluated = r.groups_evaluated;
    out.held = r.held;
    out.budget_coarsened = r.budget_coarsened;
    out.budget_forced = r.budget_forced;
    std::memcpy(result, &out, std::min<std::size_t>(size, sizeof out));
    return ACUITY_OK;
  });
}

}  // extern "C"

// ---- Foveation planner ----------------------------------------------------------------------------

struct acuity_foveation_planner {
  acuity::FoveationPlanner planner;
};

extern "C" {

void acuity_foveation_config_default_sized(acuity_foveation_config* c, size_t size) {
  if (!c || !default_size_ok(size, sizeof *c, 1)) return;
  acuity_foveation_config full;
  (acuity_foveation_config_default)(&full);
  write_defaults(&full, sizeof full, c, size);
}

void(acuity_foveation_config_default)(acuity_foveation_config* c) {
  if (!c) return;
  const acuity::FoveationConfig d;
  std::memset(c, 0, sizeof *c);
  c->struct_size = sizeof *c;
  c->threshold_model = static_cast<uint32_t>(d.model);
  c->quality = d.quality;
  c->min_gaze_confidence = d.min_gaze_confidence;
  c->gaze_uncertainty_deg = d.gaze_uncertainty_deg;
  c->no_gaze_radius_deg = d.no_gaze_radius_deg;
  c->foveal_radius_deg = d.foveal_radius_deg;
  c->max_rate = d.max_rate;
  c->head_rotation = d.head_rotation ? 1u : 0u;
}

acuity_status acuity_foveation_create(const acuity_foveation_config* c, acuity_foveation_planner** out) {
  return guarded([&] {
    if (!c || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: null pointer");
    *out = nullptr;
    if (c->struct_size < sizeof *c)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: struct_size too small");
    if (c->threshold_model > ACUITY_MODEL_STELA_CSF)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: unknown threshold_model");
    if (c->max_rate > 4)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: max_rate must be 1, 2 or 4");
    acuity::FoveationConfig f;
    f.model = static_cast<acuity::ThresholdModel>(c->threshold_model);
    f.quality = c->quality;
    f.min_gaze_confidence = c->min_gaze_confidence;
    f.gaze_uncertainty_deg = c->gaze_uncertainty_deg;
    f.no_gaze_radius_deg = c->no_gaze_radius_deg;
    f.foveal_radius_deg = c->foveal_radius_deg;
    f.max_rate = static_cast<std::uint8_t>(c->max_rate);
    f.head_rotation = c->head_rotation != 0;
    auto* p = new acuity_foveation_planner;
    if (acuity::init_foveation_planner(f, &p->planner) != acuity::FoveationStatus::Ok) {
      delete p;
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_foveation_create: quality must be > 0, radii >= 0 and finite, max_rate 1, 2 or 4");
    }
    *out = p;
    return ACUITY_OK;
  });
}

void acuity_foveation_destroy(acuity_foveation_planner* planner) { delete planner; }

acuity_status acuity_foveation_map_size(const acuity_eye* e, uint32_t tile_px, uint32_t* cols,
                                        uint32_t* rows) {
  return guarded([&] {
    if (cols) *cols = 0;
    if (rows) *rows = 0;
    if (!e || !cols || !rows) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_map_size: null pointer");
    acuity::Eye eye;
    acuity::Gaze gaze;
    eye_and_gaze(*e, &eye, &gaze);
    if (!acuity::foveation_map_size(eye, tile_px, cols, rows))
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_foveation_map_size: tile_px must be 8, 16 or 32, the viewport non-empty and at "
                  "most 2048 tiles per axis");
    return ACUITY_OK;
  });
}

acuity_status acuity_foveation_plan(const acuity_foveation_planner* p, const acuity_eye* e, uint32_t tile_px,
                                    uint32_t capacity, uint8_t* shading_rate, float* mip_bias,
                                    acuity_foveation_info* info) {
  return guarded([&] {
    if (!p || !e || !shading_rate || !mip_bias)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_plan: null pointer");
    acuity::Eye eye;
    acuity::Gaze gaze;
    eye_and_gaze(*e, &eye, &gaze);
    acuity::FoveationMaps maps;
    maps.tile_px = tile_px;
    maps.capacity = capacity;
    maps.shading_rate = shading_rate;
    maps.mip_bias = mip_bias;
    const acuity::FoveationStatus status = acuity::plan_foveation(p->planner, eye, gaze, &maps);
    if (status == acuity::FoveationStatus::InvalidArgument)
      return fail(ACUITY_INVALID_ARGUMENT,
                  "acuity_foveation_plan: tile_px must be 8, 16 or 32 and capacity at least cols x rows "
                  "(acuity_foveation_map_size)");
    if (info) {
      info->cols = maps.cols;
      info->rows = maps.rows;
      info->result = static_cast<uint32_t>(status);
      info->origin_px[0] = maps.origin_px[0];
      info->origin_px[1] = maps.origin_px[1];
      info->retinal_speed = maps.retinal_speed;
      info->shaded = maps.shaded;
      info->pixels = maps.pixels;
    }
    return ACUITY_OK;
  });
}

acuity_status acuity_foveation_layers(const acuity_foveation_planner* p, const acuity_eye* e,
                                      uint32_t n_layers, acuity_guenter_layers* out) {
  return guarded([&] {
    if (!p || !e || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_layers: null pointer");
    if (n_layers < 1 || n_layers > 8)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_layers: 1 to 8 layers");
    acuity::Eye eye;
    acuity::Gaze gaze;
    eye_and_gaze(*e, &eye, &gaze);
    const acuity::FoveationLayers l = acuity::foveation_layers(p->planner, eye, static_cast<int>(n_layers));
    std::memset(out, 0, sizeof *out);
    out->n_layers = static_cast<uint32_t>(l.layers.n_layers);
    out->omega0 = l.omega0;
    out->slope = l.slope;
    for (int i = 0; i < l.layers.n_layers; ++i) {
      out->radius_deg[i] = l.layers.radius[i];
      out->sampling[i] = l.layers.sampling[i];
      out->pixels[i] = l.layers.pixels[i];
    }
    out->speedup = l.layers.speedup;
    return ACUITY_OK;
  });
}

}  // extern "C"
