/* acuity.h — the C ABI of acuity's runtime, for engines' native plugins (Unity, Unreal, Godot).
 *
 * Plain C: no C++ types cross this boundary and no exception does; every call returns a status
 * and acuity_last_error() says what went wrong (per thread). Units as in the C++ headers: metres,
 * degrees, degrees per second, pixels. An eye looks along its local -Z with +Y up.
 *
 *   acuity_config c; acuity_config_default(&c);  c.transition_seconds = 0.25f;  (then any field)
 *   acuity_scheduler* s; acuity_create(&c, &s);
 *   int32_t p; acuity_load_profile(s, bytes, size, &p);        // the bytes are copied
 *   acuity_add_objects(s, n, profiles, positions, 0, rotations, 0, scales, ids);
 *   each frame: acuity_set_transforms(...); acuity_begin_frame(s, eyes, 2, dt);
 *               acuity_update_range(s, 0, n);  (split across jobs as you like)
 *               acuity_end_frame(s); acuity_get_levels(s, n, ids, levels, flags);
 *               acuity_get_transitions(s, n, ids, previous, fades);  (cross-fade while fade < 1)
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

/* Version 2 added: acuity_config.struct_size and every SchedulerConfig field, acuity_set_bias,
 * acuity_set_clamps, acuity_get_transitions, acuity_explain; all-or-nothing batch calls.
 * Version 3 appended acuity_config.evaluation (ACUITY_EVALUATION_*) and the foveation planner.
 * Version 4 appended acuity_config.tabulated_biases.
 * Version 5 added acuity_frame_stats and acuity_get_frame_stats.
 * Version 6 appended acuity_config.hysteresis_seconds and max_coarsen_wait_seconds.
 * Version 7 added views beyond the eyes: acuity_config.max_views and max_view_classes, acuity_view,
 * acuity_begin_frame_views and acuity_get_view_levels; and acuity_config_default_sized and
 * acuity_foveation_config_default_sized (the _default macros pass the caller's sizeof); and
 * ACUITY_MODEL_STELA_CSF (appended).
 * Version 8 added cluster cuts: acuity_hierarchy (acuity_hierarchy_create, _create_from_profile,
 * _destroy), acuity_cluster,
 * acuity_cluster_group, acuity_cut_memory_size, acuity_cut_result and acuity_select_cut.
 * Version 9 added acuity_select_cut_budget (a cut under a triangle budget) and appended
 * acuity_cut_result.budget_coarsened and budget_forced (ACUITY_CUT_RESULT_SIZE_V9).
 * Version 10 added deferred tables: acuity_load_profile_deferred and acuity_tables
 * (acuity_make_tables, acuity_make_view_tables, acuity_install_tables, acuity_tables_destroy,
 * acuity_wanted_tables).
 * Version 11 added acuity_drop_idle_tables. */
#define ACUITY_C_API_VERSION 11

typedef struct acuity_scheduler acuity_scheduler;

typedef enum acuity_status {
  ACUITY_OK = 0,
  ACUITY_INVALID_ARGUMENT = 1, /* a null pointer, a bad id or index, a count or value out of range */
  ACUITY_BAD_PROFILE = 2,      /* the profile bytes failed validation (see acuity_last_error) */
  ACUITY_FULL = 3,             /* max_objects or max_profiles reached */
  ACUITY_OUT_OF_MEMORY = 4,
  ACUITY_INTERNAL_ERROR = 5
} acuity_status;

/* acuity_config.rule (acuity::SelectionRule) */
enum {
  ACUITY_RULE_PERCEPTUAL = 0,
  ACUITY_RULE_REDDY = 1,
  ACUITY_RULE_DISTANCE = 2,
  ACUITY_RULE_SCREEN_SIZE = 3
};
/* acuity_config.model (acuity::ThresholdModel); values are only ever appended. ACUITY_MODEL_STELA_CSF
 * uses ModelParams' default luminance (100 cd/m^2) and area (+inf), which acuity_model_params does
 * not carry (see acuity/models.hpp). */
enum {
  ACUITY_MODEL_DEFAULT = 0,
  ACUITY_MODEL_GEISLER_PERRY = 1,
  ACUITY_MODEL_KELLY_DALY = 2,
  ACUITY_MODEL_REDDY = 3,
  ACUITY_MODEL_STELA_CSF = 4
};
/* acuity_config.view_blend (acuity::ViewBlend) */
enum { ACUITY_VIEW_BLEND_NEAREST = 0, ACUITY_VIEW_BLEND_MAX3 = 1 };
/* How the perceptual rule evaluates thresholds: per-profile tables (conservative, the default) or
 * every band and orientation through the model (see "The tabulated path" in acuity/scheduler.hpp). */
enum { ACUITY_EVALUATION_TABULATED = 0, ACUITY_EVALUATION_EXACT = 1 };
/* acuity_model_params.csf_fit (acuity::CsfFit) */
enum { ACUITY_CSF_DALY1998 = 0, ACUITY_CSF_LAIRD2006 = 1 };

/* Per-object flags returned by acuity_get_levels (acuity::ObjectFlag). */
enum {
  ACUITY_FLAG_INVALID_INPUT = 1,
  ACUITY_FLAG_EYE_INSIDE = 2,
  ACUITY_FLAG_NO_GAZE = 4,
  ACUITY_FLAG_BUDGET_FORCED = 8,
  ACUITY_FLAG_CHANGED = 16,
  ACUITY_FLAG_HELD = 32
};

/* Levels a profile may have (acuity::kMaxLevels). */
#define ACUITY_MAX_LEVELS 32

/* The vision model's constants (acuity::ModelParams); defaults are the published values. */
typedef struct acuity_model_params {
  double ct0;            /* Geisler-Perry minimum threshold contrast */
  double alpha;          /* Geisler-Perry spatial-frequency decay */
  double e2;             /* half-resolution eccentricity [deg] */
  double pursuit_gain;   /* Daly smooth pursuit g */
  double pursuit_min;    /* [deg/s] */
  double pursuit_max;    /* [deg/s] */
  double drift;          /* retinal velocity floor [deg/s] */
  double reddy_contrast; /* threshold contrast inside Reddy's visible region */
  uint32_t csf_fit;      /* ACUITY_CSF_* */
  uint32_t reserved;     /* must be 0 */
} acuity_model_params;

/* Scheduler settings, one field per acuity::SchedulerConfig field (see acuity/scheduler.hpp).
 *
 * Growth rule: struct_size comes first and is sizeof(acuity_config) as the caller compiled it
 * (acuity_config_default sets it). New fields are only ever appended. acuity_create accepts any
 * struct_size >= ACUITY_CONFIG_SIZE_V2 that is a multiple of 8 and <= 65536: fields beyond a
 * smaller struct_size (an older caller) take their defaults; bytes beyond the fields this library
 * knows (a newer caller) are ignored. Anything else is ACUITY_INVALID_ARGUMENT. Always call
 * acuity_config_default first, then change fields. */
typedef struct acuity_config {
  uint32_t struct_size;       /* sizeof(acuity_config); set by acuity_config_default */
  uint32_t max_objects;       /* capacity, >= 1 */
  uint32_t max_profiles;      /* capacity */
  uint32_t rule;              /* ACUITY_RULE_* */
  uint32_t model;             /* ACUITY_MODEL_* */
  uint32_t view_blend;        /* ACUITY_VIEW_BLEND_* */
  float quality;              /* q: invisible when lost <= q CT; finite, > 0 */
  uint32_t fallback_level;    /* level for invalid input (0 finest), < ACUITY_MAX_LEVELS */
  float min_gaze_confidence;  /* below it there is no gaze */
  float gaze_uncertainty_deg; /* tracker error [deg] */
  float no_gaze_radius_deg;   /* without gaze: where the gaze may be [deg] */
  float hysteresis_margin;    /* coarsening needs a score <= 1 - margin */
  uint32_t hysteresis_frames; /* ... on this many consecutive frames (alias of hysteresis_seconds) */
  float saccade_speed_deg_s;  /* > 0: coarsen only during saccades faster than this */
  uint32_t max_coarsen_wait;  /* ... or after waiting this many frames (alias, see version 6) */
  float transition_seconds;   /* cross-fade length (acuity_get_transitions) [s], >= 0 */
  uint64_t triangle_budget;   /* 0: none */
  float distance_scale;       /* ACUITY_RULE_DISTANCE: switch distances times this */
  float pixel_error;          /* ACUITY_RULE_SCREEN_SIZE: allowed projected error [px] */
  uint32_t keep_scores;       /* 1: keep every level's score (acuity_explain needs none) */
  uint32_t reserved;          /* must be 0 */
  acuity_model_params params;
  /* version 3 (appended): */
  uint32_t evaluation; /* ACUITY_EVALUATION_*; a version-2 caller gets TABULATED */
  uint32_t reserved3;  /* must be 0 */
  /* version 4 (appended): */
  float tabulated_biases[3]; /* per-object biases (acuity_set_bias) with tables of their own besides 1:
                                each 0 (unused) or finite > 0; see SchedulerConfig::tabulated_biases */
  uint32_t reserved4;        /* must be 0 */
  /* version 6 (appended): the waits in seconds of the frames' dt, finite and >= 0. A field > 0
     replaces its frame count above; 0 (the default, and what an older caller gets) keeps the frame
     count. How dt is summed: SchedulerConfig's timing in acuity/scheduler.hpp. */
  float hysteresis_seconds;       /* coarsening needs the lower score for this long [s] */
  float max_coarsen_wait_seconds; /* with saccade gating: or after waiting this long for one [s] */
  /* version 7 (appended): views beyond the eyes (acuity_view); an older caller gets 0 and 0. */
  uint32_t max_views;        /* views a frame may carry (acuity_begin_frame_views), <= 1024 */
  uint32_t max_view_classes; /* levels per object besides the eyes' (acuity_get_view_levels), <= 256 */
} acuity_config;
/* The sizes of the version-2 layout (everything up to params: the smallest struct_size
 * acuity_create accepts), of the version-3, version-4, version-6 and version-7 layouts (this one). */
#define ACUITY_CONFIG_SIZE_V2 160u
#define ACUITY_CONFIG_SIZE_V3 168u
#define ACUITY_CONFIG_SIZE_V4 184u
#define ACUITY_CONFIG_SIZE_V6 192u
#define ACUITY_CONFIG_SIZE_V7 200u

typedef struct acuity_eye {
  double position[3];             /* world [m] */
  float orientation[4];           /* unit quaternion x y z w, eye to world */
  float fov_deg[4];               /* left (<0), right, up, down (<0) */
  uint32_t viewport[2];           /* width, height [px] */
  float velocity[3];              /* world [m/s] */
  float angular_velocity[3];      /* head rotation [deg/s], world axis x speed */
  float gaze_direction[3];        /* unit, eye space */
  float gaze_confidence;          /* 0..1 */
  float gaze_angular_velocity[3]; /* [deg/s], eye space */
  uint8_t gaze_valid;
  uint8_t gaze_has_velocity;
} acuity_eye;

/* A view beyond the eyes (acuity::View, whose comments in acuity/scheduler.hpp are the contract): a
 * shadow map's light view or a secondary camera (mirror, portal, spectator). Each object gets a level
 * per view class: the finest its class's views need this frame, within its clamps. */
enum { ACUITY_PROJECTION_PERSPECTIVE = 0, ACUITY_PROJECTION_ORTHOGRAPHIC = 1 };
enum {
  ACUITY_VIEW_RULE_FOOTPRINT = 0, /* the coarsest level whose error covers <= pixel_error texels */
  ACUITY_VIEW_RULE_AS_EYE = 1     /* the scheduler's rule for an eye without gaze (perspective) */
};
typedef struct acuity_view {
  uint32_t view_class;  /* < acuity_config.max_view_classes */
  uint32_t projection;  /* ACUITY_PROJECTION_* */
  uint32_t rule;        /* ACUITY_VIEW_RULE_* (orthographic views: FOOTPRINT whatever this says) */
  float pixel_error;    /* FOOTPRINT: allowed projected error [texels or px] */
  double position[3];   /* world [m] */
  float orientation[4]; /* unit quaternion x y z w, view to world; looks along -Z, +Y up */
  float fov_deg[4];     /* perspective: half-angles left (<0), right, up, down (<0) [deg] */
  float extent_m[4];    /* orthographic: left, right, top, bottom of the map [m] */
  uint32_t viewport[2]; /* the map's or image's width, height [texels or px] */
} acuity_view;
/* The version-7 layout's size: acuity_begin_frame_views's smallest view_size. */
#define ACUITY_VIEW_SIZE_V7 96u

/* One level's score and what limits it (acuity::LevelExplain). */
typedef struct acuity_level_explain {
  float score;               /* max over bands and orientations of lost / (q CT); <= 1 invisible */
  uint8_t band, orientation; /* the limiting band and orientation */
  float frequency_cpd;       /* that band's centre at the current distance */
  float threshold;           /* CT there */
} acuity_level_explain;

/* Why an object has its level (acuity::ObjectExplain). */
typedef struct acuity_object_explain {
  float distance_m, angular_diameter_deg, eccentricity_deg, image_velocity_deg_s, retinal_velocity_deg_s;
  uint32_t view; /* the profile view used */
  uint8_t level, level_count;
  acuity_level_explain levels[ACUITY_MAX_LEVELS]; /* [level_count]; level 0 has score 0 */
} acuity_object_explain;

/* Contracts common to every function below:
 * - Ownership: the library keeps no pointer the caller passes (profile bytes are copied); every
 *   output array is the caller's, `count` elements long.
 * - Threads: one scheduler is used by one thread at a time, except acuity_update_range, which may
 *   run on many threads at once on disjoint ranges between acuity_begin_frame and acuity_end_frame.
 *   Different schedulers are independent. acuity_last_error is per thread.
 * - Failure: a call that returns anything but ACUITY_OK has changed nothing (batch calls check every
 *   id and value before touching the scheduler) and acuity_last_error() says why. ACUITY_OUT_OF_MEMORY
 *   and ACUITY_INTERNAL_ERROR may come from any call that returns a status. */

uint32_t acuity_version(void);       /* ACUITY_VERSION of the library; any thread */
const char* acuity_last_error(void); /* this thread's last message, "" if none; valid
                                                     until this thread's next acuity_ call */
/* Fills every field with the C++ defaults and struct_size = sizeof(acuity_config). Null: no-op. */
/* Fills the first `size` bytes of *config with the C++ defaults and sets struct_size = size, where
 * size is sizeof(acuity_config) as the caller compiled it: a caller built against an older, smaller
 * acuity_config is never written past (and a newer, larger one gets zeros past the fields this
 * library knows). size must follow the growth rule (>= ACUITY_CONFIG_SIZE_V2, a multiple of 8,
 * <= 65536); otherwise, or for a null config, nothing is written. C and C++ callers write
 * acuity_config_default(&c) (the macro below passes sizeof c); FFI callers (ctypes, C#, Rust) call
 * acuity_config_default_sized with their struct's size. */
void acuity_config_default_sized(acuity_config* config, size_t size);
/* The function form fills sizeof(acuity_config) of *this* library: only for callers built with this
 * very header and library together (the web module); everyone else goes through the macro. */
void(acuity_config_default)(acuity_config* config);
#define acuity_config_default(config) acuity_config_default_sized((config), sizeof *(config))
void acuity_eye_default(acuity_eye* eye); /* origin, identity, 90 deg, 1920 px, no gaze */

/* Creates a scheduler; *out receives it (the caller owns it: acuity_destroy).
 * INVALID_ARGUMENT: null config or out, struct_size outside the growth rule, max_objects 0, an
 * unknown rule/model/view_blend/csf_fit/evaluation, reserved fields not 0, quality not finite and > 0,
 * a tabulated_biases entry neither 0 nor finite and > 0,
 * fallback_level >= ACUITY_MAX_LEVELS, transition_seconds, hysteresis_seconds or
 * max_coarsen_wait_seconds negative or not finite, max_views above 1024 or max_view_classes above
 * 256. *out is unchanged
 * on failure. */
acuity_status acuity_create(const acuity_config* config, acuity_scheduler** out);
/* Frees the scheduler and the profile copies. Null: no-op. */
void acuity_destroy(acuity_scheduler* scheduler);

/* Validates and copies a profile (.acuity bytes); *index receives its index (0, 1, ...).
 * INVALID_ARGUMENT: null s, data or index. BAD_PROFILE: the bytes are not a valid profile, or size
 * is below the 32-byte header or above 4 GiB (checked before reading, so an unchecked ftell's -1
 * fails cleanly). FULL: max_profiles reached. Nothing is kept and *index is unchanged on failure. */
acuity_status acuity_load_profile(acuity_scheduler* s, const void* data, size_t size, int32_t* index);
/* The same without building the profile's tables (acuity::Scheduler::add_profile_deferred): quick
 * whatever the profile, and its objects are decided exactly until acuity_install_tables. A scene
 * of many assets starts at once; a worker thread of the host makes the tables meanwhile. */
acuity_status acuity_load_profile_deferred(acuity_scheduler* s, const void* data, size_t size,
                                           int32_t* index);

/* One profile's tables, made apart from the frame loop (acuity::ProfileTables). */
typedef struct acuity_tables acuity_tables;
/* Makes profile `profile`'s tables into *out (the caller's: acuity_install_tables or
 * acuity_tables_destroy). Thread-safe: from any thread, for several profiles at once, during frames
 * too, but not during acuity_load_profile*, acuity_install_tables or acuity_drop_idle_tables on
 * the same scheduler.
 * INVALID_ARGUMENT: null s or out, a profile not loaded, or a scheduler with no tables (exact
 * evaluation, or a rule without thresholds); *out is unchanged then. */
acuity_status acuity_make_tables(const acuity_scheduler* s, int32_t profile, acuity_tables** out);
/* The same for one view of the profile (0 to its view count - 1): about 1/(view count) of the time
 * and bytes. INVALID_ARGUMENT also for a view out of range. */
acuity_status acuity_make_view_tables(const acuity_scheduler* s, int32_t profile, uint32_t view,
                                      acuity_tables** out);
/* Installs tables this scheduler made for `profile`, outside a frame: from the next frame its
 * objects seen from their views read them (deciding as if loaded with acuity_load_profile). On OK
 * they are consumed; else they stay the caller's. INVALID_ARGUMENT: null s or tables, tables of
 * another profile or scheduler, of a view the profile has tables of, or a call between
 * acuity_begin_frame and acuity_end_frame. */
acuity_status acuity_install_tables(acuity_scheduler* s, int32_t profile, acuity_tables* tables);
/* Outside a frame: up to `capacity` views that objects were seen from without their tables since
 * the last call (each view listed once; the rest at the next call), as profiles[i], views[i]; *count
 * receives how many. For a host that makes a deferred profile's tables one view at a time
 * (acuity_make_view_tables). INVALID_ARGUMENT: null s or count, null arrays with capacity > 0, or a
 * call between acuity_begin_frame and acuity_end_frame. */
acuity_status acuity_wanted_tables(acuity_scheduler* s, int32_t* profiles, uint32_t* views, uint32_t capacity,
                                   uint32_t* count);
/* Outside a frame: frees the tables of every view (any profile's) that no object has read in the
 * last `frames` frames (its tables, or a remembered decision made from them; installing counts as a
 * read; 0 frees all). Their objects decide exactly again, and acuity_wanted_tables lists such a view
 * again when one is seen from it. *freed (may be null) receives the bytes freed. It reallocates the
 * tables kept: call it every few seconds, not every frame. INVALID_ARGUMENT: null s, or a call
 * between acuity_begin_frame and acuity_end_frame. */
acuity_status acuity_drop_idle_tables(acuity_scheduler* s, uint32_t frames, size_t* freed);
/* Frees tables not installed. Null: no-op. */
void acuity_tables_destroy(acuity_tables* tables);

/* Adds `count` objects. Arrays of `count`; strides in bytes between elements, 0 for tightly packed;
 * scales may be null (1). ids_out receives their ids (uint32).
 * INVALID_ARGUMENT: null s, or (count > 0) a null profiles/positions/rotations/ids_out, or a profile
 * index that was not loaded. FULL: fewer than `count` free slots. On failure no object was added. */
acuity_status acuity_add_objects(acuity_scheduler* s, uint32_t count, const int32_t* profiles,
                                 const double* positions, size_t position_stride, const float* rotations,
                                 size_t rotation_stride, const float* scales, uint32_t* ids_out);
/* Removes objects; their ids may be reused by later adds.
 * INVALID_ARGUMENT: null s or ids, an id that is not alive (never added, or removed: stale), or an id
 * given twice. On failure none was removed. */
acuity_status acuity_remove_objects(acuity_scheduler* s, uint32_t count, const uint32_t* ids);
/* World transforms per id (scales nullable: 1). INVALID_ARGUMENT: null s, or (count > 0) null
 * ids/positions/rotations, an id not alive. On failure no transform changed. Non-finite values are
 * accepted and give those objects ACUITY_FLAG_INVALID_INPUT and the fallback level. */
acuity_status acuity_set_transforms(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                    const double* positions, size_t position_stride, const float* rotations,
                                    size_t rotation_stride, const float* scales);
/* World velocities [m/s] per id (else derived from transforms and dt). INVALID_ARGUMENT: null s,
 * ids or velocities (count > 0), an id not alive. On failure no velocity changed. */
acuity_status acuity_set_velocities(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                    const float* velocities, size_t velocity_stride);
/* Per-object quality bias: multiplies q for that object (> 1 coarser, < 1 finer; 1 by default).
 * INVALID_ARGUMENT: null s, ids or biases (count > 0), an id not alive, a bias not finite and > 0.
 * On failure no bias changed. */
acuity_status acuity_set_bias(acuity_scheduler* s, uint32_t count, const uint32_t* ids, const float* biases);
/* Per-object level clamps: the level stays in [min_level, max_level] (0 and 255 by default; a clamp
 * past the profile's coarsest level means its coarsest). INVALID_ARGUMENT: null s, ids, min_levels
 * or max_levels (count > 0), an id not alive, max_level < min_level. On failure no clamp changed. */
acuity_status acuity_set_clamps(acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                const uint8_t* min_levels, const uint8_t* max_levels);

/* The frame: begin_frame, then update_range over [0, max_objects) split as you like (ranges past
 * max_objects are clipped), then end_frame (budget, transitions, statistics).
 * begin_frame INVALID_ARGUMENT: null s or eyes, eye_count not 1 or 2, a frame already begun.
 * update_range / end_frame INVALID_ARGUMENT: null s, no frame begun. A failed call leaves the frame
 * state as it was. Levels, flags and transitions read between frames are the last end_frame's. */
acuity_status acuity_begin_frame(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count, float dt);
/* acuity_begin_frame with views beyond the eyes: view_count views, each view_size bytes apart
 * (sizeof(acuity_view) as the caller compiled it; the growth rule of acuity_config: at least
 * ACUITY_VIEW_SIZE_V7, a multiple of 8, <= 65536, bytes past the known fields ignored). Views with
 * non-finite values, a non-unit orientation, an empty field of view or extent, or a 0 viewport are
 * accepted and give their objects the fallback level. INVALID_ARGUMENT as acuity_begin_frame, and
 * for null views (view_count > 0), view_count above max_views, a bad view_size, a view_class not
 * below max_view_classes, or an unknown projection or rule (views[i] named); nothing begun then. */
acuity_status acuity_begin_frame_views(acuity_scheduler* s, const acuity_eye* eyes, uint32_t eye_count,
                                       float dt, const acuity_view* views, uint32_t view_count,
                                       size_t view_size);
acuity_status acuity_update_range(acuity_scheduler* s, uint32_t first, uint32_t count);
acuity_status acuity_end_frame(acuity_scheduler* s);

/* levels_out and flags_out (nullable) receive one byte per id (ACUITY_FLAG_*).
 * INVALID_ARGUMENT: null s, ids or levels_out (count > 0), an id not alive; outputs untouched then. */
acuity_status acuity_get_levels(const acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                uint8_t* levels_out, uint8_t* flags_out);
/* Each id's level for view class view_class this frame (after acuity_end_frame; a class no view
 * named: the coarsest level its clamps allow). INVALID_ARGUMENT: null s, ids or levels_out
 * (count > 0), view_class not below max_view_classes, an id not alive; outputs untouched then. */
acuity_status acuity_get_view_levels(const acuity_scheduler* s, uint32_t view_class, uint32_t count,
                                     const uint32_t* ids, uint8_t* levels_out);
/* Cross-fade state per id: the level faded from and the fade to the current level, 0..1 (1 = done;
 * it rises by dt / transition_seconds per frame after a change; always 1 when transition_seconds is 0).
 * While fade < 1 draw both levels, the current one with weight fade. Either output may be null.
 * INVALID_ARGUMENT: null s or ids (count > 0), an id not alive; outputs untouched then. */
acuity_status acuity_get_transitions(const acuity_scheduler* s, uint32_t count, const uint32_t* ids,
                                     uint8_t* previous_levels_out, float* fades_out);
/* Recomputes one object for the current frame with every level's score (slow: for debugging UIs).
 * INVALID_ARGUMENT: null s or out, an id not alive; *out untouched then. */
acuity_status acuity_explain(const acuity_scheduler* s, uint32_t id, acuity_object_explain* out);
/* Triangles drawn at this frame's levels; 0 for null. */
uint64_t acuity_frame_triangles(const acuity_scheduler* s);

/* The last acuity_end_frame's counts over the live objects (acuity::FrameStats; all 0 before the
 * first). Growth rule as acuity_config's: the caller sets struct_size = sizeof(acuity_frame_stats)
 * as it compiled it; fields are only ever appended, and this library writes the fields it knows
 * (a newer caller's further bytes are left as they were). */
typedef struct acuity_frame_stats {
  uint32_t struct_size;   /* sizeof(acuity_frame_stats), set by the caller */
  uint32_t changed;       /* objects whose level changed (ACUITY_FLAG_CHANGED) */
  uint64_t triangles;     /* drawn at the chosen levels (as acuity_frame_triangles) */
  uint32_t budget_forced; /* objects the triangle budget pushed past visibility */
  uint32_t invalid;       /* objects with ACUITY_FLAG_INVALID_INPUT */
  uint32_t at_rest;       /* objects decided at rest: from their memos, without their geometry */
  uint8_t gaze_used;      /* 1: a gaze was used this frame */
  uint8_t reserved[3];    /* written 0 */
} acuity_frame_stats;
/* The size of the version-5 layout, the smallest struct_size accepted. */
#define ACUITY_FRAME_STATS_SIZE_V5 32
/* INVALID_ARGUMENT: null s or out, struct_size below ACUITY_FRAME_STATS_SIZE_V5, not a multiple of
 * 8 or above 65536; *out untouched then. */
acuity_status acuity_get_frame_stats(const acuity_scheduler* s, acuity_frame_stats* out);

/* ---- Cluster cuts (acuity/clusters.hpp; docs/design.md section 6, "Cluster cuts") -----------------
 * Detail that follows the gaze inside one object: a cluster hierarchy (lodgen's --clusters,
 * docs/lodgen.md) and what each group's simplification loses per band; each frame the cut (the
 * clusters to draw) for an object placed in the world, from the scheduler's eyes and gaze.
 *
 *   acuity_hierarchy* h; acuity_hierarchy_create(clusters, nc, groups, ng, bands, nb, diameter, lost, &h);
 *   void* memory = calloc(1, acuity_cut_memory_size(h));   (one per object; zeroed: nothing remembered)
 *   uint32_t* drawn = malloc(nc * sizeof *drawn);
 *   each frame, after acuity_begin_frame:
 *     acuity_cut_result r; r.struct_size = sizeof r;
 *     acuity_select_cut(s, h, position, rotation, scale, velocity, memory, size, nc, drawn, &r);
 *     draw clusters drawn[0 .. r.clusters)
 *   acuity_hierarchy_destroy(h);
 */
typedef struct acuity_hierarchy acuity_hierarchy;

/* acuity_cluster.group of a root, .refined of a finest cluster (acuity::kNoGroup). */
#define ACUITY_NO_GROUP 0xFFFFFFFFu
/* One cluster (acuity::Cluster, 16 bytes): a run of the hierarchy's triangles. */
typedef struct acuity_cluster {
  uint32_t first_triangle; /* into the hierarchy's index array (triangle t: indices 3t .. 3t+2) */
  uint32_t triangle_count; /* 1 .. 128 */
  uint32_t group;          /* the group it is a member of, or ACUITY_NO_GROUP: a root */
  uint32_t refined;        /* the group whose simplification made it, or ACUITY_NO_GROUP: finest */
} acuity_cluster;
/* One group (acuity::ClusterGroup, 32 bytes). */
typedef struct acuity_cluster_group {
  float center[3];       /* bounding sphere [object units] */
  float radius;          /* >= 0 */
  float error;           /* of the clusters it made [object units], >= its members' makers' */
  uint32_t first_member; /* its members: clusters first_member .. first_member + member_count - 1 */
  uint32_t member_count;
  uint32_t level; /* 0 when its members are finest, else 1 + the largest level of their makers */
} acuity_cluster_group;

/* Copies and checks a hierarchy and its loss (the arrays may be freed after the call). clusters
 * and groups as lodgen's ACUITY_cluster_hierarchy stores them (finest clusters first, covering the
 * index array in order; a group after every group that made one of its members); bands_cpod:
 * band_count band centres [cycles per `diameter`], increasing, 1 .. 32; diameter [object units],
 * finite > 0; lost: group_count x band_count lost contrasts (row per group; NaN counts as visible).
 * INVALID_ARGUMENT: a null pointer (lost and groups may be null when group_count is 0), no cluster,
 * a band count out of range, a non-finite or non-positive diameter or band, or records that fail
 * acuity::check_cluster_records (acuity_last_error names the cluster or group). */
acuity_status acuity_hierarchy_create(const acuity_cluster* clusters, uint32_t cluster_count,
                                      const acuity_cluster_group* groups, uint32_t group_count,
                                      const float* bands_cpod, uint32_t band_count, float diameter,
                                      const float* lost, acuity_hierarchy** out);
/* The same with the loss read from the object's profile (.acuity bytes, copied and validated;
 * BAD_PROFILE otherwise): the profile of the hierarchy's own glTF (`acuity profile OUT.glb`) gives
 * each group's measured loss (its Clusters section, and per view cell its ClusterViews section when
 * it measured 162 directions per group: acuity::measured_group_loss, as C++ and Python's
 * acuity.clusters.load read it);
 * BAD_PROFILE when that section measured another hierarchy (group count or hash differ). A profile
 * without one (a chain of the same mesh) gives the fallback, acuity::provisional_group_loss
 * (acuity/clusters.hpp). */
acuity_status acuity_hierarchy_create_from_profile(const acuity_cluster* clusters, uint32_t cluster_count,
                                                   const acuity_cluster_group* groups, uint32_t group_count,
                                                   const void* profile, size_t profile_size,
                                                   acuity_hierarchy** out);
void acuity_hierarchy_destroy(acuity_hierarchy* hierarchy); /* null: no-op */
/* Bytes of one object's cut memory for this hierarchy (0 for null): what the cut remembers between
 * frames (hysteresis and saccade gating per group) and its walk's and budget's scratch (version 9:
 * 21 bytes per group, was 13; always ask this function). The caller allocates it
 * 4-byte aligned and zeroed (nothing remembered: the next cut takes its groups at once), one per
 * object drawn with the hierarchy, and keeps it between frames. */
size_t acuity_cut_memory_size(const acuity_hierarchy* hierarchy);

/* acuity_cut_result.status */
enum {
  ACUITY_CUT_OK = 0,           /* the perceptual cut */
  ACUITY_CUT_INVALID_INPUT = 1 /* non-finite or non-unit transform, scale <= 0, non-finite velocity or
                                  no valid eye: the finest cut (ACUITY_FLAG_INVALID_INPUT) */
};
/* What acuity_select_cut did (acuity::CutResult). Growth rule as acuity_frame_stats': the caller sets
 * struct_size = sizeof(acuity_cut_result) as it compiled it (at least ACUITY_CUT_RESULT_SIZE_V8, a
 * multiple of 8, at most 65536); fields are only appended; the library writes the ones it knows
 * (and no byte beyond struct_size: a version-8 caller's 32 bytes get the version-8 fields). */
typedef struct acuity_cut_result {
  uint32_t struct_size;      /* sizeof(acuity_cut_result), set by the caller */
  uint32_t status;           /* ACUITY_CUT_* */
  uint32_t flags;            /* ACUITY_FLAG_INVALID_INPUT, _EYE_INSIDE, _NO_GAZE, _HELD, _BUDGET_FORCED */
  uint32_t clusters;         /* drawn: drawn[0 .. clusters) */
  uint64_t triangles;        /* drawn */
  uint32_t groups_evaluated; /* groups whose thresholds were evaluated */
  uint32_t held;             /* groups kept visible by hysteresis or saccade gating */
  /* Version 9: */
  uint32_t budget_coarsened; /* visible groups the triangle budget coarsened (acuity_select_cut_budget) */
  uint32_t budget_forced;    /* ... of them a visible loss (score > 1; ACUITY_FLAG_BUDGET_FORCED) */
} acuity_cut_result;
#define ACUITY_CUT_RESULT_SIZE_V8 32u
#define ACUITY_CUT_RESULT_SIZE_V9 40u

/* One object's cut this frame (acuity::Scheduler::select_cut with memory): after acuity_begin_frame
 * (the frame's eyes and gaze, this scheduler's model, quality, gaze handling, hysteresis and saccade
 * gating; the perceptual rule's thresholds, evaluated exactly, whatever rule and evaluation say).
 * The object at position [m, world], rotation (unit quaternion x y z w, object to world) and uniform
 * scale, moving at velocity [m/s, world; null: still]. Call it once per frame per object: each call
 * is one frame of the hysteresis. memory: acuity_cut_memory_size(h) bytes, 4-byte aligned, this
 * object's (calls on different memories may run concurrently). drawn receives the cluster ids to
 * draw; capacity must be at least the hierarchy's cluster count (so a cut always fits).
 * INVALID_ARGUMENT (nothing written, memory unchanged): a null s, h, position, rotation, memory,
 * drawn or result, memory_size too small or memory misaligned, capacity below the cluster count, a
 * bad result struct_size, no frame begun yet. Invalid object or eye values are not an error: the
 * finest cut, status ACUITY_CUT_INVALID_INPUT. */
acuity_status acuity_select_cut(const acuity_scheduler* s, const acuity_hierarchy* h,
                                const double position[3], const float rotation[4], float scale,
                                const float* velocity, void* memory, size_t memory_size, uint32_t capacity,
                                uint32_t* drawn, acuity_cut_result* result);
/* The same under a triangle budget (acuity::Scheduler::select_cut with a CutBudget; 0: none, as
 * acuity_select_cut): when the cut draws more than triangle_budget triangles, the visible groups
 * whose loss is least visible per triangle saved are coarsened first, one whole group at a time
 * (crack-free), until it draws at most the budget or only groups an eye is inside are left to
 * coarsen; result->budget_coarsened and budget_forced (ACUITY_FLAG_BUDGET_FORCED) say what it cost. */
acuity_status acuity_select_cut_budget(const acuity_scheduler* s, const acuity_hierarchy* h,
                                       const double position[3], const float rotation[4], float scale,
                                       const float* velocity, uint64_t triangle_budget, void* memory,
                                       size_t memory_size, uint32_t capacity, uint32_t* drawn,
                                       acuity_cut_result* result);

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
  uint32_t struct_size;       /* sizeof(acuity_foveation_config): set by _default */
  uint32_t threshold_model;   /* ACUITY_MODEL_*: 0 default .. 4 stela-csf */
  float quality;              /* q: a lost component is invisible at contrast <= q CT */
  float min_gaze_confidence;  /* below it (or gaze_valid == 0, or a non-finite gaze) there is no gaze */
  float gaze_uncertainty_deg; /* subtracted from every eccentricity */
  float no_gaze_radius_deg;   /* without gaze: eccentricity from this disc around the view centre */
  float foveal_radius_deg;    /* full rate within this of where the gaze may be */
  uint32_t max_rate;          /* coarsest pixels per shade: 1, 2 or 4 */
  uint32_t head_rotation;     /* nonzero: the head's angular velocity lowers the cutoff (default 0:
                                  the vestibulo-ocular reflex holds the fixated world still) */
} acuity_foveation_config;

/* Statuses of acuity_foveation_plan beyond acuity_status: the maps were written in both cases. */
enum {
  ACUITY_FOVEATION_GAZE = 0,       /* planned around the gaze */
  ACUITY_FOVEATION_NO_GAZE = 1,    /* no usable gaze: planned around the no-gaze disc */
  ACUITY_FOVEATION_INVALID_EYE = 2 /* non-finite or degenerate eye: full rate, bias 0 everywhere */
};

typedef struct acuity_foveation_info {
  uint32_t cols, rows; /* tiles written */
  uint32_t result;     /* ACUITY_FOVEATION_* */
  float origin_px[2];  /* the gaze (or view centre) in pixels, x right, y down; may lie off the image */
  float retinal_speed; /* the speed the cutoff was taken at [deg/s] */
  double shaded;       /* shading work: sum over tiles of pixels / (rate_x rate_y) */
  double pixels;       /* full-rate work: width x height */
} acuity_foveation_info;

typedef struct acuity_guenter_layers {
  uint32_t n_layers;    /* 0 when the eye was invalid */
  double omega0, slope; /* the MAR line below the model [deg per cycle], [per deg] */
  double radius_deg[8]; /* e_i; the outer layer's is the display's half-angle */
  double sampling[8];   /* s_i >= 1: layer pixel size in display pixels */
  double pixels[8];     /* P_i: each layer's pixel count */
  double speedup;       /* display pixels / layer pixels */
} acuity_guenter_layers;

/* As acuity_config_default_sized: the first `size` bytes (at least this version's size and at most
 * 65536; else nothing is written), struct_size = size; the macro passes sizeof. */
void acuity_foveation_config_default_sized(acuity_foveation_config* config, size_t size);
void(acuity_foveation_config_default)(acuity_foveation_config* config);
#define acuity_foveation_config_default(config) \
  acuity_foveation_config_default_sized((config), sizeof *(config))
/* INVALID_ARGUMENT for a null pointer, a struct_size smaller than this version's, an unknown model
 * or out-of-range values; OUT_OF_MEMORY when the ~125 KB of tables cannot be allocated. */
acuity_status acuity_foveation_create(const acuity_foveation_config* config, acuity_foveation_planner** out);
void acuity_foveation_destroy(acuity_foveation_planner* planner);
/* Tiles per axis for the eye's viewport; INVALID_ARGUMENT (and 0) for tile_px not 8, 16 or 32, an
 * empty viewport or more than 2048 tiles per axis. */
acuity_status acuity_foveation_map_size(const acuity_eye* eye, uint32_t tile_px, uint32_t* cols,
                                        uint32_t* rows);
/* One eye, one frame, allocation-free. shading_rate: 2 bytes per tile (x then y); mip_bias: one
 * float per tile; capacity: tiles both buffers hold, at least cols x rows. info is nullable.
 * INVALID_ARGUMENT (nothing written) for null pointers, a bad tile size or too small a capacity;
 * otherwise ACUITY_OK with info->result saying whether the gaze, the no-gaze disc or (for an invalid
 * eye) full rate everywhere was used. */
acuity_status acuity_foveation_plan(const acuity_foveation_planner* planner, const acuity_eye* eye,
                                    uint32_t tile_px, uint32_t capacity, uint8_t* shading_rate,
                                    float* mip_bias, acuity_foveation_info* info);
/* Guenter layers for the eye's display from the same model (allocates: once per display). */
acuity_status acuity_foveation_layers(const acuity_foveation_planner* planner, const acuity_eye* eye,
                                      uint32_t n_layers, acuity_guenter_layers* out);

#ifdef __cplusplus
}
#endif
#endif /* ACUITY_H */
