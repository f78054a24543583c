/* acuity_web.c — the few entry points web/acuity.js needs besides acuity.h, compiled only into
 * the WebAssembly module. They keep the JavaScript free of struct layouts: acuity_config and
 * acuity_eye grow fields over time, so the JS names config fields and passes eyes as flat doubles,
 * and this file (compiled against the same acuity.h) does the layout.
 */
#include <string.h>

#include "acuity.h"

/* One eye as ACUITY_WEB_EYE_DOUBLES doubles, in this order:
 *   position[3] (world m), orientation[4] (x y z w, eye to world), fov_deg[4] (left right up down),
 *   viewport[2] (px), velocity[3] (m/s), angular_velocity[3] (deg/s, world axis x speed),
 *   gaze_direction[3] (unit, eye space), gaze_confidence, gaze_angular_velocity[3] (deg/s),
 *   gaze_valid (0/1), gaze_has_velocity (0/1). */
enum { ACUITY_WEB_EYE_DOUBLES = 28 };

uint32_t acuity_web_eye_doubles(void) { return ACUITY_WEB_EYE_DOUBLES; }
size_t acuity_web_config_size(void) { return sizeof(acuity_config); }

/* Sets one acuity_config field by name; ACUITY_INVALID_ARGUMENT for a name it does not know or a
 * value that does not fit the field (negative or fractional counts, out-of-range integers). */
acuity_status acuity_web_config_set(acuity_config* c, const char* name, double v) {
  if (!c || !name) return ACUITY_INVALID_ARGUMENT;
#define ACUITY_WEB_FLOAT(field)    \
  if (strcmp(name, #field) == 0) { \
    c->field = (float)v;           \
    return ACUITY_OK;              \
  }
#define ACUITY_WEB_UINT(field, max)                                                                  \
  if (strcmp(name, #field) == 0) {                                                                   \
    if (!(v >= 0 && v <= (double)(max)) || v != (double)(uint64_t)v) return ACUITY_INVALID_ARGUMENT; \
    c->field = (uint64_t)v;                                                                          \
    return ACUITY_OK;                                                                                \
  }
  ACUITY_WEB_UINT(max_objects, UINT32_MAX)
  ACUITY_WEB_UINT(max_profiles, UINT32_MAX)
  ACUITY_WEB_UINT(rule, UINT32_MAX)
  ACUITY_WEB_UINT(evaluation, UINT32_MAX)
  ACUITY_WEB_FLOAT(quality)
  ACUITY_WEB_FLOAT(gaze_uncertainty_deg)
  ACUITY_WEB_FLOAT(no_gaze_radius_deg)
  ACUITY_WEB_FLOAT(hysteresis_margin)
  ACUITY_WEB_UINT(hysteresis_frames, UINT32_MAX)
  ACUITY_WEB_FLOAT(hysteresis_seconds)
  ACUITY_WEB_FLOAT(saccade_speed_deg_s)
  ACUITY_WEB_UINT(max_coarsen_wait, UINT32_MAX)
  ACUITY_WEB_FLOAT(max_coarsen_wait_seconds)
  ACUITY_WEB_UINT(triangle_budget, 9007199254740992.0) /* 2^53: exact in a double */
  ACUITY_WEB_UINT(max_views, UINT32_MAX)
  ACUITY_WEB_UINT(max_view_classes, UINT32_MAX)
#undef ACUITY_WEB_FLOAT
#undef ACUITY_WEB_UINT
  return ACUITY_INVALID_ARGUMENT;
}

static void copy_floats(float* out, const double* in, int n) {
  for (int k = 0; k < n; ++k) out[k] = (float)in[k];
}

/* One view beyond the eyes as ACUITY_WEB_VIEW_DOUBLES doubles, in this order: view_class,
 * projection (ACUITY_PROJECTION_*), rule (ACUITY_VIEW_RULE_*), pixel_error, position[3] (world m),
 * orientation[4] (x y z w, view to world), fov_deg[4] (left right up down), extent_m[4] (left right
 * top bottom), viewport[2] (texels or px). Integers out of their range become values the C ABI
 * refuses. */
enum { ACUITY_WEB_VIEW_DOUBLES = 21, ACUITY_WEB_MAX_VIEWS = 64 };
uint32_t acuity_web_view_doubles(void) { return ACUITY_WEB_VIEW_DOUBLES; }

static uint32_t to_uint(double v) { return v >= 0 && v <= 4294967295.0 ? (uint32_t)v : UINT32_MAX; }

/* acuity_begin_frame_views with eyes as eye_count x ACUITY_WEB_EYE_DOUBLES doubles and views as
 * view_count x ACUITY_WEB_VIEW_DOUBLES (at most ACUITY_WEB_MAX_VIEWS). */
acuity_status acuity_web_begin_frame(acuity_scheduler* s, const double* data, uint32_t eye_count, float dt,
                                     const double* view_data, uint32_t view_count) {
  acuity_eye eyes[2];
  acuity_view views[ACUITY_WEB_MAX_VIEWS];
  if (!data || eye_count < 1 || eye_count > 2)
    return acuity_begin_frame(s, NULL, eye_count, dt); /* its message */
  if (view_count > ACUITY_WEB_MAX_VIEWS || (view_count > 0 && !view_data))
    return ACUITY_INVALID_ARGUMENT; /* acuity.js says why before calling */
  for (uint32_t i = 0; i < view_count; ++i) {
    const double* d = view_data + i * ACUITY_WEB_VIEW_DOUBLES;
    acuity_view* v = &views[i];
    v->view_class = to_uint(d[0]);
    v->projection = to_uint(d[1]);
    v->rule = to_uint(d[2]);
    v->pixel_error = (float)d[3];
    for (int k = 0; k < 3; ++k) v->position[k] = d[4 + k];
    copy_floats(v->orientation, d + 7, 4);
    copy_floats(v->fov_deg, d + 11, 4);
    copy_floats(v->extent_m, d + 15, 4);
    for (int k = 0; k < 2; ++k) v->viewport[k] = d[19 + k] >= 0 && d[19 + k] <= 1e9 ? (uint32_t)d[19 + k] : 0;
  }
  for (uint32_t i = 0; i < eye_count; ++i) {
    const double* d = data + i * ACUITY_WEB_EYE_DOUBLES;
    acuity_eye* e = &eyes[i];
    acuity_eye_default(e);
    for (int k = 0; k < 3; ++k) e->position[k] = d[k];
    copy_floats(e->orientation, d + 3, 4);
    copy_floats(e->fov_deg, d + 7, 4);
    for (int k = 0; k < 2; ++k) {
      const double px = d[11 + k];
      e->viewport[k] = px >= 0 && px <= 1e9 ? (uint32_t)px : 0; /* 0: rejected by the scheduler */
    }
    copy_floats(e->velocity, d + 13, 3);
    copy_floats(e->angular_velocity, d + 16, 3);
    copy_floats(e->gaze_direction, d + 19, 3);
    e->gaze_confidence = (float)d[22];
    copy_floats(e->gaze_angular_velocity, d + 23, 3);
    e->gaze_valid = d[26] != 0;
    e->gaze_has_velocity = d[27] != 0;
  }
  if (view_count == 0) return acuity_begin_frame(s, eyes, eye_count, dt);
  return acuity_begin_frame_views(s, eyes, eye_count, dt, views, view_count, sizeof(acuity_view));
}
