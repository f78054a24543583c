// The C ABI over acuity::Scheduler: every entry point catches everything.
#include "acuity.h"

#include <cstring>
#include <deque>
#include <new>
#include <string>

#include "acuity/file.hpp"
#include "acuity/foveation_plan.hpp"
#include "acuity/scheduler.hpp"
#include "acuity/version.hpp"

struct acuity_scheduler {
  acuity::Scheduler scheduler;
  std::deque<acuity::Blob> profiles;  // the bytes every Profile points into (stable addresses)
  std::uint32_t live = 0;             // objects added and not removed
  bool frame_begun = false;           // acuity_begin_frame was called at least once
  explicit acuity_scheduler(const acuity::SchedulerConfig& c) : scheduler(c) {}
};

namespace {
thread_local std::string g_error;

acuity_status fail(acuity_status status, std::string message) {
  g_error = std::move(message);
  return status;
}

template <class Fn> acuity_status guarded(Fn fn) {
  try {
    g_error.clear();
    return fn();
  } catch (const std::bad_alloc&) {
    return fail(ACUITY_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(ACUITY_INTERNAL_ERROR, e.what());
  } catch (...) {
    return fail(ACUITY_INTERNAL_ERROR, "unknown error");
  }
}

template <class T> const T* element(const T* base, std::size_t stride, std::size_t i, std::size_t packed) {
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

acuity::ObjectTransform transform(const double* p, std::size_t ps, const float* r, std::size_t rs, const float* s, std::size_t i) {
  acuity::ObjectTransform t;
  const double* pi = element(p, ps, i, 3 * sizeof(double));
  const float* ri = element(r, rs, i, 4 * sizeof(float));
  for (int k = 0; k < 3; ++k) t.position[k] = pi[k];
  for (int k = 0; k < 4; ++k) t.rotation[k] = ri[k];
  t.scale = s ? s[i] : 1.0f;
  return t;
}

// INVALID_ARGUMENT naming the first of `ids` that is not a live object, or OK: checked before any
// change, so a call with one stale id changes nothing.
acuity_status check_alive(const acuity_scheduler* s, uint32_t count, const uint32_t* ids, const char* function) {
  for (uint32_t i = 0; i < count; ++i)
    if (!s->scheduler.alive(ids[i]))
      return fail(ACUITY_INVALID_ARGUMENT, std::string(function) + ": ids[" + std::to_string(i) + "] = " + std::to_string(ids[i]) +
                                               " is not a live object (never added, or removed); nothing was changed");
  return ACUITY_OK;
}
}  // namespace

extern "C" {

uint32_t acuity_version(void) { return ACUITY_VERSION; }
const char* acuity_last_error(void) { return g_error.c_str(); }

void acuity_config_default(acuity_config* c) {
  if (!c) return;
  const acuity::SchedulerConfig d;
  c->max_objects = d.max_objects;
  c->max_profiles = d.max_profiles;
  c->rule = ACUITY_RULE_PERCEPTUAL;
  c->quality = d.quality;
  c->gaze_uncertainty_deg = d.gaze_uncertainty_deg;
  c->no_gaze_radius_deg = d.no_gaze_radius_deg;
  c->hysteresis_margin = d.hysteresis_margin;
  c->hysteresis_frames = d.hysteresis_frames;
  c->saccade_speed_deg_s = d.saccade_speed;
  c->triangle_budget = d.triangle_budget;
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
    if (c->rule > ACUITY_RULE_SCREEN_SIZE || c->max_objects == 0) return fail(ACUITY_INVALID_ARGUMENT, "acuity_create: bad rule or capacity");
    acuity::SchedulerConfig sc;
    sc.max_objects = c->max_objects;
    sc.max_profiles = c->max_profiles;
    sc.rule = static_cast<acuity::SelectionRule>(c->rule);
    sc.quality = c->quality;
    sc.gaze_uncertainty_deg = c->gaze_uncertainty_deg;
    sc.no_gaze_radius_deg = c->no_gaze_radius_deg;
    sc.hysteresis_margin = c->hysteresis_margin;
    sc.hysteresis_frames = c->hysteresis_frames;
    sc.saccade_speed = c->saccade_speed_deg_s;
    sc.triangle_budget = c->triangle_budget;
    *out = new acuity_scheduler(sc);
    return ACUITY_OK;
  });
}

void acuity_destroy(acuity_scheduler* s) { delete s; }

acuity_status acuity_load_profile(acuity_scheduler* s, const void* data, size_t size, int32_t* index) {
  return guarded([&] {
    if (!s || !data || !index) return fail(ACUITY_INVALID_ARGUMENT, "acuity_load_profile: null argument");
    // At least the 32-byte header, at most 4 GiB (profiles are kilobytes to megabytes): refuses an
    // unchecked ftell's -1 before (size + 7) / 8 below could wrap, and 0 before a memcpy to null.
    if (size < 32 || size > std::size_t(UINT32_MAX))
      return fail(ACUITY_BAD_PROFILE, "acuity_load_profile: size " + std::to_string(size) + " bytes is not a profile's size");
    if (s->profiles.size() >= s->scheduler.config().max_profiles)
      return fail(ACUITY_FULL, "acuity_load_profile: max_profiles (" + std::to_string(s->scheduler.config().max_profiles) + ") reached");
    acuity::Blob blob;
    blob.size = size;
    blob.storage.assign((size + 7) / 8, 0);
    std::memcpy(blob.storage.data(), data, size);
    acuity::Profile p;
    acuity::ProfileError e;
    if (acuity::open_profile(blob.data(), blob.size, &p, &e) != acuity::ProfileStatus::Ok)
      return fail(ACUITY_BAD_PROFILE, std::string(acuity::to_string(e.status)) + ": " + e.message);
    s->profiles.push_back(std::move(blob));
    acuity::open_profile(s->profiles.back().data(), s->profiles.back().size, &p);  // point into the kept copy
    const int i = s->scheduler.add_profile(p);
    if (i < 0) {
      s->profiles.pop_back();
      return fail(ACUITY_FULL, "acuity_load_profile: max_profiles reached");
    }
    *index = i;
    return ACUITY_OK;
  });
}

acuity_status acuity_add_objects(acuity_scheduler* s, uint32_t count, const int32_t* profiles, const double* positions,
                                 size_t ps, const float* rotations, size_t rs, const float* scales, uint32_t* ids) {
  return guarded([&] {
    if (!s || (count && (!profiles || !positions || !rotations || !ids))) return fail(ACUITY_INVALID_ARGUMENT, "acuity_add_objects: null argument");
    // All or nothing: every index and the capacity are checked before anything is added.
    for (uint32_t i = 0; i < count; ++i)
      if (profiles[i] < 0 || std::size_t(profiles[i]) >= s->profiles.size())
        return fail(ACUITY_INVALID_ARGUMENT, "acuity_add_objects: profiles[" + std::to_string(i) + "] = " + std::to_string(profiles[i]) +
                                                 " is not a loaded profile (" + std::to_string(s->profiles.size()) + " loaded); nothing was added");
    if (count > s->scheduler.object_capacity() - s->live)
      return fail(ACUITY_FULL, "acuity_add_objects: " + std::to_string(count) + " objects do not fit (" + std::to_string(s->live) + " of " +
                                   std::to_string(s->scheduler.object_capacity()) + " used); nothing was added");
    for (uint32_t i = 0; i < count; ++i) {
      ids[i] = s->scheduler.add_object(profiles[i], transform(positions, ps, rotations, rs, scales, i));
      if (ids[i] == acuity::kInvalidObject) {  // cannot happen after the checks above; undo to keep the contract
        for (uint32_t j = 0; j < i; ++j) s->scheduler.remove_object(ids[j]);
        s->live -= i;
        return fail(ACUITY_INTERNAL_ERROR, "acuity_add_objects: the scheduler refused object " + std::to_string(i) + "; nothing was added");
      }
      ++s->live;
    }
    return ACUITY_OK;
  });
}

acuity_status acuity_remove_objects(acuity_scheduler* s, uint32_t count, const uint32_t* ids) {
  return guarded([&] {
    if (!s || (count && !ids)) return fail(ACUITY_INVALID_ARGUMENT, "acuity_remove_objects: null argument");
    if (const acuity_status st = check_alive(s, count, ids, "acuity_remove_objects"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i)
      for (uint32_t j = 0; j < i; ++j)
        if (ids[i] == ids[j])
          return fail(ACUITY_INVALID_ARGUMENT, "acuity_remove_objects: id " + std::to_string(ids[i]) + " is given twice; nothing was removed");
    for (uint32_t i = 0; i < count; ++i) s->scheduler.remove_object(ids[i]);
    s->live -= count;
    return ACUITY_OK;
  });
}

acuity_status acuity_set_transforms(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const double* positions,
                                    size_t ps, const float* rotations, size_t rs, const float* scales) {
  return guarded([&] {
    if (!s || (count && (!ids || !positions || !rotations))) return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_transforms: null argument");
    if (const acuity_status st = check_alive(s, count, ids, "acuity_set_transforms"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i) s->scheduler.set_transform(ids[i], transform(positions, ps, rotations, rs, scales, i));
    return ACUITY_OK;
  });
}

acuity_status acuity_set_velocities(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const float* v, size_t vs) {
  return guarded([&] {
    if (!s || (count && (!ids || !v))) return fail(ACUITY_INVALID_ARGUMENT, "acuity_set_velocities: null argument");
    if (const acuity_status st = check_alive(s, count, ids, "acuity_set_velocities"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i) s->scheduler.set_velocity(ids[i], element(v, vs, i, 3 * sizeof(float)));
    return ACUITY_OK;
  });
}

acuity_status acuity_begin_frame(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count, float dt) {
  return guarded([&] {
    if (!s || !eyes || eye_count < 1 || eye_count > 2) return fail(ACUITY_INVALID_ARGUMENT, "acuity_begin_frame: one or two eyes");
    acuity::Frame f;
    f.eye_count = eye_count;
    f.dt = dt;
    for (uint32_t i = 0; i < eye_count; ++i) {
      const acuity_eye& e = eyes[i];
      std::memcpy(f.eyes[i].position, e.position, sizeof e.position);
      std::memcpy(f.eyes[i].orientation, e.orientation, sizeof e.orientation);
      std::memcpy(f.eyes[i].fov_deg, e.fov_deg, sizeof e.fov_deg);
      std::memcpy(f.eyes[i].viewport, e.viewport, sizeof e.viewport);
      std::memcpy(f.eyes[i].velocity, e.velocity, sizeof e.velocity);
      std::memcpy(f.eyes[i].angular_velocity, e.angular_velocity, sizeof e.angular_velocity);
      std::memcpy(f.gaze[i].direction, e.gaze_direction, sizeof e.gaze_direction);
      std::memcpy(f.gaze[i].angular_velocity, e.gaze_angular_velocity, sizeof e.gaze_angular_velocity);
      f.gaze[i].confidence = e.gaze_confidence;
      f.gaze[i].valid = e.gaze_valid != 0;
      f.gaze[i].has_velocity = e.gaze_has_velocity != 0;
    }
    s->scheduler.begin_frame(f);
    s->frame_begun = true;
    return ACUITY_OK;
  });
}

acuity_status acuity_update_range(acuity_scheduler* s, uint32_t first, uint32_t count) {
  return guarded([&] {
    if (!s) return fail(ACUITY_INVALID_ARGUMENT, "acuity_update_range: null scheduler");
    if (!s->frame_begun)
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_update_range: no frame has begun (call acuity_begin_frame first); nothing was updated");
    s->scheduler.update(first, count);
    return ACUITY_OK;
  });
}

acuity_status acuity_end_frame(acuity_scheduler* s) {
  return guarded([&] {
    if (!s) return fail(ACUITY_INVALID_ARGUMENT, "acuity_end_frame: null scheduler");
    if (!s->frame_begun) return fail(ACUITY_INVALID_ARGUMENT, "acuity_end_frame: no frame has begun (call acuity_begin_frame first)");
    s->scheduler.end_frame();
    return ACUITY_OK;
  });
}

acuity_status acuity_get_levels(const acuity_scheduler* s, uint32_t count, const uint32_t* ids, uint8_t* levels, uint8_t* flags) {
  return guarded([&] {
    if (!s || (count && (!ids || !levels))) return fail(ACUITY_INVALID_ARGUMENT, "acuity_get_levels: null argument");
    if (const acuity_status st = check_alive(s, count, ids, "acuity_get_levels"); st != ACUITY_OK) return st;
    for (uint32_t i = 0; i < count; ++i) {
      levels[i] = s->scheduler.level(ids[i]);
      if (flags) flags[i] = s->scheduler.flags(ids[i]);
    }
    return ACUITY_OK;
  });
}

uint64_t acuity_frame_triangles(const acuity_scheduler* s) { return s ? s->scheduler.stats().triangles : 0; }

}  // extern "C"

// ---- Foveation planner ----------------------------------------------------------------------------

struct acuity_foveation_planner {
  acuity::FoveationPlanner planner;
};

extern "C" {

void acuity_foveation_config_default(acuity_foveation_config* c) {
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
    if (c->struct_size < sizeof *c) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: struct_size too small");
    if (c->threshold_model > 3) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: unknown threshold_model");
    if (c->max_rate > 4) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: max_rate must be 1, 2 or 4");
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
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_create: quality must be > 0, radii >= 0 and finite, max_rate 1, 2 or 4");
    }
    *out = p;
    return ACUITY_OK;
  });
}

void acuity_foveation_destroy(acuity_foveation_planner* planner) { delete planner; }

acuity_status acuity_foveation_map_size(const acuity_eye* e, uint32_t tile_px, uint32_t* cols, uint32_t* rows) {
  return guarded([&] {
    if (cols) *cols = 0;
    if (rows) *rows = 0;
    if (!e || !cols || !rows) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_map_size: null pointer");
    acuity::Eye eye;
    acuity::Gaze gaze;
    eye_and_gaze(*e, &eye, &gaze);
    if (!acuity::foveation_map_size(eye, tile_px, cols, rows))
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_map_size: tile_px must be 8, 16 or 32, the viewport non-empty and at most 2048 tiles per axis");
    return ACUITY_OK;
  });
}

acuity_status acuity_foveation_plan(const acuity_foveation_planner* p, const acuity_eye* e, uint32_t tile_px,
                                    uint32_t capacity, uint8_t* shading_rate, float* mip_bias,
                                    acuity_foveation_info* info) {
  return guarded([&] {
    if (!p || !e || !shading_rate || !mip_bias) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_plan: null pointer");
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
      return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_plan: tile_px must be 8, 16 or 32 and capacity at least cols x rows (acuity_foveation_map_size)");
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

acuity_status acuity_foveation_layers(const acuity_foveation_planner* p, const acuity_eye* e, uint32_t n_layers,
                                      acuity_guenter_layers* out) {
  return guarded([&] {
    if (!p || !e || !out) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_layers: null pointer");
    if (n_layers < 1 || n_layers > 8) return fail(ACUITY_INVALID_ARGUMENT, "acuity_foveation_layers: 1 to 8 layers");
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
