/* acuity.h — the C ABI of acuity's runtime, for engines' native plugins (Unity, Unreal, Godot).
 *
 * Plain C: no C++ types cross this boundary and no exception does; every call returns a status
 * and acuity_last_error() says what went wrong (per thread). Units as in the C++ headers: metres,
 * degrees, degrees per second, pixels. An eye looks along its local -Z with +Y up.
 *
 *   acuity_config c; acuity_config_default(&c);
 *   acuity_scheduler* s; acuity_create(&c, &s);
 *   int32_t p; acuity_load_profile(s, bytes, size, &p);        // the bytes are copied
 *   acuity_add_objects(s, n, profiles, positions, 0, rotations, 0, scales, ids);
 *   each frame: acuity_set_transforms(...); acuity_begin_frame(s, eyes, 2, dt);
 *               acuity_update_range(s, 0, n);  (split across jobs as you like)
 *               acuity_end_frame(s); acuity_get_levels(s, n, ids, levels, flags);
 *   acuity_destroy(s);
 *
 * Contract. The caller is trusted: pointers must point to arrays of the stated length and stride,
 * and one scheduler is used from one thread at a time (acuity_update_range on disjoint ranges may
 * run concurrently between begin and end). Everything else is checked. Every call that takes ids
 * or indices is all or nothing: it checks them all (and the capacity) first and, when one is bad,
 * changes nothing and returns ACUITY_INVALID_ARGUMENT (ACUITY_FULL for capacity). A removed or
 * never-added id is invalid everywhere. Profile bytes are untrusted: validated, never trusted.
 */
#ifndef ACUITY_H
#define ACUITY_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ACUITY_C_API_VERSION 1

typedef struct acuity_scheduler acuity_scheduler;

typedef enum acuity_status {
  ACUITY_OK = 0,
  ACUITY_INVALID_ARGUMENT = 1,  /* a null pointer, a bad id or index, a count out of range */
  ACUITY_BAD_PROFILE = 2,       /* the profile bytes failed validation (see acuity_last_error) */
  ACUITY_FULL = 3,              /* max_objects or max_profiles reached */
  ACUITY_OUT_OF_MEMORY = 4,
  ACUITY_INTERNAL_ERROR = 5
} acuity_status;

enum { ACUITY_RULE_PERCEPTUAL = 0, ACUITY_RULE_REDDY = 1, ACUITY_RULE_DISTANCE = 2, ACUITY_RULE_SCREEN_SIZE = 3 };

/* Per-object flags returned by acuity_get_levels. */
enum {
  ACUITY_FLAG_INVALID_INPUT = 1, ACUITY_FLAG_EYE_INSIDE = 2, ACUITY_FLAG_NO_GAZE = 4,
  ACUITY_FLAG_BUDGET_FORCED = 8, ACUITY_FLAG_CHANGED = 16, ACUITY_FLAG_HELD = 32
};

typedef struct acuity_config {
  uint32_t max_objects;          /* capacity */
  uint32_t max_profiles;         /* capacity */
  uint32_t rule;                 /* ACUITY_RULE_* */
  float quality;                 /* q: invisible when lost <= q CT */
  float gaze_uncertainty_deg;
  float no_gaze_radius_deg;
  float hysteresis_margin;
  uint32_t hysteresis_frames;
  float saccade_speed_deg_s;     /* > 0: coarsen during saccades */
  uint64_t triangle_budget;      /* 0: none */
} acuity_config;

typedef struct acuity_eye {
  double position[3];            /* world [m] */
  float orientation[4];          /* unit quaternion x y z w, eye to world */
  float fov_deg[4];              /* left (<0), right, up, down (<0) */
  uint32_t viewport[2];          /* width, height [px] */
  float velocity[3];             /* world [m/s] */
  float angular_velocity[3];     /* head rotation [deg/s], world axis x speed */
  float gaze_direction[3];       /* unit, eye space */
  float gaze_confidence;         /* 0..1 */
  float gaze_angular_velocity[3];/* [deg/s], eye space */
  uint8_t gaze_valid;
  uint8_t gaze_has_velocity;
} acuity_eye;

uint32_t acuity_version(void);                    /* ACUITY_VERSION of the library */
const char* acuity_last_error(void);              /* this thread's last message, "" if none */
void acuity_config_default(acuity_config* config);
void acuity_eye_default(acuity_eye* eye);         /* origin, identity, 90 deg, 1920 px, no gaze */

acuity_status acuity_create(const acuity_config* config, acuity_scheduler** out);
void acuity_destroy(acuity_scheduler* scheduler);

/* Validates and copies a profile (.acuity bytes); *index receives its index. size must be the
 * bytes' length: below the 32-byte header or above 4 GiB gives ACUITY_BAD_PROFILE without reading
 * (so an unchecked ftell's -1 fails cleanly); invalid bytes ACUITY_BAD_PROFILE; max_profiles
 * loaded ACUITY_FULL. On failure nothing is kept and *index is unchanged. */
acuity_status acuity_load_profile(acuity_scheduler* s, const void* data, size_t size, int32_t* index);

/* Arrays of `count`; strides in bytes between elements, 0 for tightly packed. ids_out: uint32.
 * All or nothing: a profiles[i] that is not a loaded index gives ACUITY_INVALID_ARGUMENT, more
 * objects than free capacity ACUITY_FULL; either way no object is added. */
acuity_status acuity_add_objects(acuity_scheduler* s, uint32_t count, const int32_t* profiles,
                                 const double* positions, size_t position_stride,
                                 const float* rotations, size_t rotation_stride,
                                 const float* scales, uint32_t* ids_out);
/* All or nothing: an id that is not live, or given twice, gives ACUITY_INVALID_ARGUMENT and
 * removes none. A removed id may be reused by a later acuity_add_objects. */
acuity_status acuity_remove_objects(acuity_scheduler* s, uint32_t count, const uint32_t* ids);
/* acuity_set_transforms, acuity_set_velocities: all or nothing; an id that is not live gives
 * ACUITY_INVALID_ARGUMENT and sets none. */
acuity_status acuity_set_transforms(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                    const double* positions, size_t position_stride,
                                    const float* rotations, size_t rotation_stride, const float* scales);
acuity_status acuity_set_velocities(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                    const float* velocities, size_t velocity_stride);

acuity_status acuity_begin_frame(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count, float dt);
/* Before the first acuity_begin_frame, acuity_update_range and acuity_end_frame return
 * ACUITY_INVALID_ARGUMENT and do nothing. */
acuity_status acuity_update_range(acuity_scheduler* s, uint32_t first, uint32_t count);
acuity_status acuity_end_frame(acuity_scheduler* s);

/* levels_out and flags_out (nullable) receive one byte per id. An id that is not live gives
 * ACUITY_INVALID_ARGUMENT and writes nothing. */
acuity_status acuity_get_levels(const acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                uint8_t* levels_out, uint8_t* flags_out);
/* Triangles drawn at this frame's levels. */
uint64_t acuity_frame_triangles(const acuity_scheduler* s);

/* ---- Foveation planner (acuity/foveation_plan.hpp) --------------------------------------------
 * Per eye and frame: a variable-rate-shading image (pixels per shade in x and y: 1, 2 or 4) and a
 * texture mip-bias map, one entry per tile, row-major with row 0 at the top of the image,
 * ceil(viewport / tile_px) tiles per axis; and the Guenter et al. 2012 layers for the eye's display.
 *
 *   acuity_foveation_config c; acuity_foveation_config_default(&c);
 *   acuity_foveation_planner* p; acuity_foveation_create(&c, &p);      (builds tables: ~ms, once)
 *   uint32_t cols, rows; acuity_foveation_map_size(&eye, 16, &cols, &rows);
 *   uint8_t rate[2 * cols * rows]; float bias[cols * rows];
 *   each frame, each eye: acuity_foveation_plan(p, &eye, 16, cols * rows, rate, bias, &info);
 *   acuity_foveation_destroy(p);
 */
typedef struct acuity_foveation_planner acuity_foveation_planner;

typedef struct acuity_foveation_config {
  uint32_t struct_size;          /* sizeof(acuity_foveation_config): set by _default */
  uint32_t threshold_model;      /* 0 default, 1 geisler-perry, 2 kelly-daly, 3 reddy */
  float quality;                 /* q: a lost component is invisible at contrast <= q CT */
  float min_gaze_confidence;     /* below it (or gaze_valid == 0, or a non-finite gaze) there is no gaze */
  float gaze_uncertainty_deg;    /* subtracted from every eccentricity */
  float no_gaze_radius_deg;      /* without gaze: eccentricity from this disc around the view centre */
  float foveal_radius_deg;       /* full rate within this of where the gaze may be */
  uint32_t max_rate;             /* coarsest pixels per shade: 1, 2 or 4 */
  uint32_t head_rotation;        /* nonzero: the head's angular velocity lowers the cutoff */
} acuity_foveation_config;

/* Statuses of acuity_foveation_plan beyond acuity_status: the maps were written in both cases. */
enum {
  ACUITY_FOVEATION_GAZE = 0,     /* planned around the gaze */
  ACUITY_FOVEATION_NO_GAZE = 1,  /* no usable gaze: planned around the no-gaze disc */
  ACUITY_FOVEATION_INVALID_EYE = 2  /* non-finite or degenerate eye: full rate, bias 0 everywhere */
};

typedef struct acuity_foveation_info {
  uint32_t cols, rows;           /* tiles written */
  uint32_t result;               /* ACUITY_FOVEATION_* */
  float origin_px[2];            /* the gaze (or view centre) in pixels, x right, y down; may lie off the image */
  float retinal_speed;           /* the speed the cutoff was taken at [deg/s] */
  double shaded;                 /* shading work: sum over tiles of pixels / (rate_x rate_y) */
  double pixels;                 /* full-rate work: width x height */
} acuity_foveation_info;

typedef struct acuity_guenter_layers {
  uint32_t n_layers;             /* 0 when the eye was invalid */
  double omega0, slope;          /* the MAR line below the model [deg per cycle], [per deg] */
  double radius_deg[8];          /* e_i; the outer layer's is the display's half-angle */
  double sampling[8];            /* s_i >= 1: layer pixel size in display pixels */
  double pixels[8];              /* P_i: each layer's pixel count */
  double speedup;                /* display pixels / layer pixels */
} acuity_guenter_layers;

void acuity_foveation_config_default(acuity_foveation_config* config);
/* INVALID_ARGUMENT for a null pointer, a struct_size smaller than this version's, an unknown model
 * or out-of-range values; OUT_OF_MEMORY when the ~125 KB of tables cannot be allocated. */
acuity_status acuity_foveation_create(const acuity_foveation_config* config, acuity_foveation_planner** out);
void acuity_foveation_destroy(acuity_foveation_planner* planner);
/* Tiles per axis for the eye's viewport; INVALID_ARGUMENT (and 0) for tile_px not 8, 16 or 32, an
 * empty viewport or more than 2048 tiles per axis. */
acuity_status acuity_foveation_map_size(const acuity_eye* eye, uint32_t tile_px, uint32_t* cols, uint32_t* rows);
/* One eye, one frame, allocation-free. shading_rate: 2 bytes per tile (x then y); mip_bias: one
 * float per tile; capacity: tiles both buffers hold, at least cols x rows. info is nullable.
 * INVALID_ARGUMENT (nothing written) for null pointers, a bad tile size or too small a capacity;
 * otherwise ACUITY_OK with info->result saying whether the gaze, the no-gaze disc or (for an invalid
 * eye) full rate everywhere was used. */
acuity_status acuity_foveation_plan(const acuity_foveation_planner* planner, const acuity_eye* eye, uint32_t tile_px,
                                    uint32_t capacity, uint8_t* shading_rate, float* mip_bias,
                                    acuity_foveation_info* info);
/* Guenter layers for the eye's display from the same model (allocates: once per display). */
acuity_status acuity_foveation_layers(const acuity_foveation_planner* planner, const acuity_eye* eye,
                                      uint32_t n_layers, acuity_guenter_layers* out);

#ifdef __cplusplus
}
#endif
#endif /* ACUITY_H */
