#pragma once
// acuity/scheduler.hpp — per-frame perceptual level-of-detail selection (docs/design.md section 6).
//
// Shape: every array is sized at creation; begin_frame / update / end_frame allocate nothing, start
// no threads and are deterministic (same inputs, same bits). update() takes an object range so a
// host job system can split the work; ranges may run concurrently between begin_frame and
// end_frame (they write disjoint objects).
//
//   acuity::Scheduler s(config);
//   int p = s.add_profile(profile);                  // a validated acuity::Profile
//   ObjectId id = s.add_object(p, transform);
//   each frame: s.set_transform(id, ...); s.begin_frame(frame); s.update(0, s.object_capacity());
//               s.end_frame(); draw level s.level(id)
//
// Conventions (docs/design.md section 3): world positions in metres (double), angles in degrees,
// angular velocities in deg/s. An eye looks along its local -Z with +Y up (OpenXR, OpenGL).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "acuity/clusters.hpp"
#include "acuity/models.hpp"
#include "acuity/profile.hpp"

namespace acuity {

// The rules, each described in selection_rules() (below): Perceptual is the default, Distance and
// ScreenSize are the engines' usual baselines.
enum class SelectionRule : std::uint8_t { Perceptual, Reddy, Distance, ScreenSize };

// How the perceptual rule evaluates thresholds each frame.
enum class Evaluation : std::uint8_t {
  Tabulated,  // default: per profile, the largest invisible angular size of each level on a grid over
              // eccentricity and retinal speed, built at add_profile; a decision may be finer than
              // Exact's, never coarser (conservative); see "The tabulated path" below
  Exact,      // every band and orientation through the threshold model, per object and frame
};

// How the profile's nearest views are combined for a runtime direction.
enum class ViewBlend : std::uint8_t {
  Nearest,  // the nearest stored view
  Max3,     // the largest lost contrast among the three nearest (conservative)
};

// Per-object status bits, set each frame.
enum ObjectFlag : std::uint8_t {
  kFlagInvalidInput = 1 << 0,  // non-finite transform or velocity, or a radius <= 0: fallback level
  kFlagEyeInside = 1 << 1,     // an eye is inside the bounding sphere: finest level
  kFlagNoGaze = 1 << 2,        // no usable gaze: fixed foveation was assumed
  kFlagBudgetForced = 1 << 3,  // the triangle budget pushed the object to a visible loss
  kFlagChanged = 1 << 4,       // the level changed this frame (a change event)
  kFlagHeld = 1 << 5,          // a coarser level was allowed but hysteresis or saccade gating held it
};

// Per-object biases besides 1 that the tabulated path keeps tables of their own for.
inline constexpr std::uint32_t kMaxTabulatedBiases = 3;

struct SchedulerConfig {
  std::uint32_t max_objects = 4096;  // capacity, fixed at creation
  std::uint32_t max_profiles = 256;  // capacity, fixed at creation
  SelectionRule rule = SelectionRule::Perceptual;
  Evaluation evaluation = Evaluation::Tabulated;  // Perceptual rule only; explain() is always Exact
  ThresholdModel model = ThresholdModel::Default;
  ModelParams params;
  // The area law (Rovamo et al. 1993 as stelaCSF fits it: params.stela.a0, f0): a loss of extent A
  // [deg^2] has its threshold raised by sqrt(1 + A_c(f) / A), A_c(f) = a0 / (1 + (f / f0)^2), so a
  // small patch of lost detail is judged as the eye sums it, not as a full-field grating. A is the
  // profile's pooled extent (its Pooled section; without it a bound from its Detail section) times
  // the squared angular diameter; with neither the area is unbounded (factor 1). Perceptual rule,
  // models Default, GeislerPerry and KellyDaly, and StelaCsf on a profile with a Pooled section at
  // params.area +inf (its own area term at A is exactly this factor; without Pooled it pools the
  // Detail section's channels). Reddy has no contrast.
  bool area_law = true;
  ViewBlend view_blend = ViewBlend::Nearest;  // lowest measured error (docs/spectra.md); Max3 errs safe
  float quality = 1.0f;                       // q: invisible when lost <= q CT (q < 1 is more conservative)
  std::uint8_t fallback_level = 0;            // level for invalid input (finest by default)
  // Per-object biases (set_bias) the tabulated path keeps tables for beside bias 1's: each finite
  // entry > 0 and != 1 (others unused; 0 by default) adds bias 1's table memory again per profile.
  // An object whose bias is one of them (or 1) is decided through that bias's tables, as a
  // configuration of quality q x bias decides it; one of any other bias by the exact path.
  float tabulated_biases[kMaxTabulatedBiases] = {0, 0, 0};

  // Gaze
  float min_gaze_confidence = 0.5f;   // below it (or when invalid or non-finite) there is no gaze
  float gaze_uncertainty_deg = 1.0f;  // tracker error: subtracted from every eccentricity [deg]
  float no_gaze_radius_deg = 30.0f;   // without gaze the gaze may be anywhere this close to the
                                      // view centre: eccentricity is measured from that disc [deg]
  // Hysteresis and timing. A finer level applies at once; a coarser one once it has been wanted for
  // hysteresis_seconds and, with saccade gating, then in a saccade or after waiting
  // max_coarsen_wait_seconds more for one (kFlagHeld meanwhile): without a saccade it goes once
  // wanted for the sum of the two. Time is the sum of the frames' dt (Frame::dt, the time since the
  // previous frame; counted in full however large, while a dt that is 0, negative or not finite
  // counts none) over the consecutive frames that wanted a coarser level, this one's included. A
  // sum reaches a wait within a relative 1e-4 of it (float rounding of many dt) and never reaches
  // +inf (forever). The same seconds give the same times at any frame rate, to within one frame.
  // The frame counts are aliases for one release: a seconds field > 0 replaces its frame count,
  // which is then ignored; at 0 (the default), negative or NaN the frame count applies, each frame
  // counting one whatever its dt (so the defaults still wait 30 frames for a saccade). A wait after
  // a hysteresis of n >= 2 frames counts from that frame (in frames or in the later frames' dt); a
  // hysteresis of 0 or 1 frames is none. At a steady frame time dt, n frames wait as n x dt
  // seconds. Frame counts above 2^24 act as 2^24.
  float hysteresis_margin = 0.0f;         // coarsening needs a score <= 1 - margin
  float hysteresis_seconds = 0.0f;        // ... held that long [s] (> 0; else hysteresis_frames)
  std::uint32_t hysteresis_frames = 0;    // ... alias: on this many consecutive frames
  float saccade_speed = 0.0f;             // > 0: coarsen only while gaze speed exceeds it [deg/s]; during
                                          // such a saccade the eye counts as fixating (the level is seen
                                          // after it, so the saccade's retinal blur is not spent) ...
  float max_coarsen_wait_seconds = 0.0f;  // ... or after waiting this long for one [s] (> 0; else ...)
  std::uint32_t max_coarsen_wait = 30;    // ... alias: after waiting this many frames for a saccade
  float transition_seconds = 0.0f;        // cross-fade length reported by transition() [s]

  // Budget (Funkhouser & Sequin): 0 = none; else coarsen greedily by least harm per triangle saved
  // (a budget turns keep_scores on: harm is the next level's score)
  std::uint64_t triangle_budget = 0;

  // Baselines
  float distance_scale = 1.0f;  // Distance: d_k = geometric error k / tan(1 arcmin), times this
  float pixel_error = 1.0f;     // ScreenSize: allowed projected geometric error [px]

  bool keep_scores = false;  // keep every level's score for scores()

  // Views beyond the eyes (View, below): how many a frame may carry, and how many view classes
  // (each a level per object: view_level_array()). Both fixed at creation; 0: the eyes only.
  std::uint32_t max_views = 0;
  std::uint32_t max_view_classes = 0;
};

// Every selection rule, once, in SelectionRule order: its name (the one Python, the simulation's
// outputs and the C ABI's documentation use; Python writes '-' as '_') and what it does. A new rule
// touches the enum above, this list and its chooser (scheduler/src), and the C ABI's ACUITY_RULE_*.
struct RuleInfo {
  SelectionRule rule;
  const char* name;  // "perceptual", "reddy", "distance", "screen-size"
  const char* help;  // one line
};
std::span<const RuleInfo> selection_rules();

// The names of selection_rules() and of Evaluation ("tabulated", "exact"); "unknown" out of range.
// parse_evaluation returns false for an unknown name.
const char* to_string(SelectionRule rule);
const char* to_string(Evaluation evaluation);
bool parse_evaluation(const char* name, Evaluation* out);

struct Eye {
  double position[3] = {0, 0, 0};            // world [m]
  float orientation[4] = {0, 0, 0, 1};       // unit quaternion x y z w, eye to world
  float fov_deg[4] = {-45, 45, 45, -45};     // half-angles left (<0), right, up, down (<0) [deg]
  std::uint32_t viewport[2] = {1920, 1920};  // width, height [px]
  float velocity[3] = {0, 0, 0};             // world [m/s]
  float angular_velocity[3] = {0, 0, 0};     // head rotation, world axis times speed [deg/s]
};

struct Gaze {
  float direction[3] = {0, 0, -1};        // unit, eye space
  float confidence = 1.0f;                // 0..1
  float angular_velocity[3] = {0, 0, 0};  // eye-in-head rotation, eye-space axis times speed [deg/s]
  bool valid = false;
  bool has_velocity = false;  // else retinal velocity follows Daly's pursuit model
};

// A view beyond the eyes: a shadow map's light view or a secondary camera (a mirror, a portal, a
// spectator or recording camera). Nobody looks through it with a gaze: each object gets a level
// for it from its geometry, and per view class (view_class) the finer need of the class's views
// wins, as the two eyes' does (a shadow class of four cascades; a mirror class). The eyes' level,
// hysteresis, budget and fades are untouched by views; a view's level applies at once, within the
// object's clamps. Conventions as an Eye's: world metres, looks along its local -Z with +Y up.
enum class ViewRule : std::uint8_t {
  // The coarsest level whose geometric error, projected into this view, covers at most
  // pixel_error texels (a shadow map) or pixels: a level never coarser than its footprint can show.
  // Orthographic: error x max(viewport[0] / width, viewport[1] / height) texels, wherever the object
  // lies. Perspective: the largest stretch of the projection anywhere in the bounding sphere, error
  // x f / w x sqrt(1 + ((|x| + r) / w)^2 + ((|y| + r) / w)^2) with f the larger focal length [px],
  // (x, y) the centre across the view axis and w = its depth - r; a sphere reaching the view's plane
  // takes the finest level, one wholly behind it the coarsest (it is not in the view).
  Footprint,
  // As the scheduler's rule decides for an eye without gaze at this view's pose, field of view and
  // resolution (the perceptual rules through the exact path: a view costs about what explain()
  // does per object). Perspective views only: an orthographic one decides by Footprint.
  AsEye,
};
enum class ViewProjection : std::uint8_t { Perspective, Orthographic };

struct View {
  std::uint32_t view_class = 0;  // < SchedulerConfig::max_view_classes
  ViewProjection projection = ViewProjection::Perspective;
  ViewRule rule = ViewRule::Footprint;
  float pixel_error = 1.0f;        // Footprint: allowed projected error [texels or px]; <= 0 or NaN:
                                   // only an error of 0 (0) or none (< 0, NaN) passes: finest
  double position[3] = {0, 0, 0};  // world [m]: the light or camera (orthographic: any point on its axis)
  float orientation[4] = {0, 0, 0, 1};       // unit quaternion x y z w, view to world
  float fov_deg[4] = {-45, 45, 45, -45};     // perspective: half-angles left (<0), right, up, down (<0)
  float extent_m[4] = {-10, 10, 10, -10};    // orthographic: left, right, top, bottom of the map [m]
  std::uint32_t viewport[2] = {2048, 2048};  // the map's or image's width, height [texels or px]
};

struct Frame {
  Eye eyes[2];
  Gaze gaze[2];
  std::uint32_t eye_count = 1;  // 1 or 2
  float dt = 0;                 // since the previous frame [s]; 0 derives no velocity
  // Views beyond the eyes, view_count of them (the caller's array, read in begin_frame only): at
  // most SchedulerConfig::max_views are read (the first ones), and a view whose view_class is not
  // below max_view_classes is skipped. A view with a non-finite value, a non-unit orientation, an
  // empty field of view or extent, or a viewport of 0 is invalid: its objects take the fallback
  // level (as for an invalid eye). A class no view names this frame gives every object its
  // coarsest level allowed (nothing draws it there).
  const View* views = nullptr;
  std::uint32_t view_count = 0;
};

struct ObjectTransform {
  double position[3] = {0, 0, 0};    // world [m]
  float rotation[4] = {0, 0, 0, 1};  // unit quaternion x y z w, object to world
  float scale = 1.0f;                // uniform
};

using ObjectId = std::uint32_t;
inline constexpr ObjectId kInvalidObject = 0xffffffffu;

// Why a level was chosen: the score of one level and what limits it.
struct LevelExplain {
  float score;        // max over bands and orientations of lost / (q CT) (stela-csf on a profile
                      // with a Detail section: the channels pooled, kBandPooling); <= 1 is invisible
  std::uint8_t band;  // the limiting band and orientation (the largest lost / CT)
  std::uint8_t orientation;
  float frequency_cpd;  // that band's centre at the current distance
  float threshold;      // CT there
};

struct ObjectExplain {
  // image_velocity_deg_s: the angular speed the eye must follow to hold the object still on the
  // retina: its motion in the world (with a measured gaze velocity), else the slower of its motion
  // in the world and in the turning head (the vestibulo-ocular reflex cancels the head's rotation).
  // retinal_velocity_deg_s: what is left after the measured gaze velocity or Daly's pursuit model.
  float distance_m, angular_diameter_deg, eccentricity_deg, image_velocity_deg_s, retinal_velocity_deg_s;
  std::uint32_t view;  // the profile view used
  std::uint8_t level, level_count;
  LevelExplain levels[kMaxLevels];  // [level_count]; level 0 has score 0
};

struct FrameStats {
  std::uint64_t triangles = 0;      // drawn at the chosen levels
  std::uint32_t changed = 0;        // objects whose level changed
  std::uint32_t budget_forced = 0;  // objects the budget pushed past visibility
  std::uint32_t invalid = 0;        // objects with kFlagInvalidInput
  std::uint32_t at_rest = 0;        // objects decided at rest: from their memos, without their geometry
  bool gaze_used = false;
};

// The tabulated path (Evaluation::Tabulated, the default for the perceptual rule). add_profile builds,
// per profile, view and level, the largest invisible angular size on grids over eccentricity and
// retinal speed, for q, q x hysteresis margin and each of SchedulerConfig::tabulated_biases
// (table_bytes() says how much; `acuity inspect` prints it). A decision may be finer than Exact's,
// never coarser. A level's score is the object's angular size over that largest invisible size (<= 1
// invisible), so the budget, hysteresis margin and keep_scores work from the tables. Decisions are
// remembered per object and eye with the bounds of the inputs they stand under (memo, 32 bytes; the
// view's hold, 40; a rest with a still eye, 12; allocated at creation): while the inputs stay inside,
// later frames take the same decision, bit for bit, without reading a table, and objects at rest
// without their geometry (FrameStats::at_rest). keep_scores or a triangle budget make every object
// read its tables instead. KellyDaly and StelaCsf (their thresholds fall with speed at low
// frequencies) and objects of an unlisted bias evaluate exactly. How it works: docs/design.md section 6.
// A scene of many assets need not wait for, nor hold, every profile's tables: add_profile_deferred()
// registers a profile without them (its objects decide exactly meanwhile: Evaluation::Exact's
// decisions), make_tables() builds them, all or one view's, on any thread, install_tables() hands
// them over between frames. wanted_tables() lists the views objects were seen from without tables,
// so a host makes only those: a profile then holds the tables of the views its objects are seen
// from (each about 1/V of the whole), and drop_idle_tables() frees those no longer seen.
class ProfileTables;
// A view of a profile that an object of it was seen from, in a frame, without that view's tables
// (the object decided exactly): one of wanted_tables()'s.
struct TablesWanted {
  std::int32_t profile;
  std::uint32_t view;
};
class Scheduler {
 public:
  explicit Scheduler(const SchedulerConfig& config);
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Registers a profile (its bytes must outlive the scheduler). Returns its index, or -1 when full.
  int add_profile(const Profile& profile);
  // The same without building its tables (the tabulated path; elsewhere as add_profile): quick
  // whatever the profile, and until install_tables() its objects are decided exactly.
  int add_profile_deferred(const Profile& profile);
  // Profile p's tables, as add_profile would build them: of every view (kAllViews; about 0.16 s of
  // one core for a 32-view profile with a hysteresis margin), or of one view v in [0, V) (about 1/V
  // of that, time and bytes). Empty when p or v is out of range, or the configuration has none.
  // Const and thread-safe: call it from any thread, for several profiles or views at once, during
  // frames too, but not during add_profile*, install_tables or drop_idle_tables.
  static constexpr int kAllViews = -1;
  ProfileTables make_tables(int profile, int view = kAllViews) const;
  // Installs tables made by this scheduler's make_tables(p, ...) for p, between end_frame() and the
  // next begin_frame(): from the next frame p's objects seen from their views read them (their
  // decisions then exactly as if p had been added with add_profile). Returns false, changing
  // nothing, for tables made for another profile or scheduler, empty ones, or of a view p already
  // has tables of.
  bool install_tables(int profile, ProfileTables&& tables);
  // Between frames: up to out.size() views (profile, view) objects were seen from without their
  // tables since the last call, each listed once until its tables are dropped; returns how many it
  // wrote (the rest come at the next call). For a host that makes a deferred profile's tables one
  // view at a time.
  std::uint32_t wanted_tables(std::span<TablesWanted> out);
  // Between frames: frees the tables of every view (any profile's, deferred or not) that no object
  // has read in the last `frames` frames (its tables, or a memo made from them; installing counts
  // as a read; 0 drops all). Their objects then decide exactly, and wanted_tables() lists the view
  // again when one is seen from it. Returns the bytes freed. It reallocates the tables it keeps (not
  // per frame: every few seconds, or when table_bytes() says a budget is passed).
  std::size_t drop_idle_tables(std::uint32_t frames);

  // Objects. add returns kInvalidObject when full or the profile index is bad. min/max clamp the
  // level; bias multiplies q for this object (see SchedulerConfig::tabulated_biases).
  ObjectId add_object(int profile, const ObjectTransform& transform);
  void remove_object(ObjectId id);
  void set_transform(ObjectId id, const ObjectTransform& transform);
  void set_velocity(ObjectId id,
                    const float velocity[3]);  // world [m/s]; else derived from transforms and dt
  void set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level);
  void set_bias(ObjectId id, float quality_bias);

  // The frame: begin, update ranges (any split), end (budget, transitions, statistics).
  void begin_frame(const Frame& frame);
  void update(std::uint32_t first, std::uint32_t count);
  void end_frame();
  void run_frame(const Frame& frame) {
    begin_frame(frame);
    update(0, object_capacity());
    end_frame();
  }

  std::uint32_t object_capacity() const;
  bool alive(ObjectId id) const;
  std::uint8_t level(ObjectId id) const;
  std::uint8_t flags(ObjectId id) const;
  // Cross-fade: the previous level and how far the fade to the current one is (1 = done).
  std::uint8_t previous_level(ObjectId id) const;
  float transition(ObjectId id) const;
  // Every level's score this frame (needs keep_scores); nullptr otherwise.
  const float* scores(ObjectId id) const;
  // The same four for every slot at once, object_capacity() entries each, indexed by ObjectId (free
  // slots hold stale values: check alive()). The arrays live as long as the scheduler; read them
  // between end_frame() and the next begin_frame(). A host reading many objects per frame indexes
  // these: the per-object calls above are out of line.
  const std::uint8_t* level_array() const;
  const std::uint8_t* flag_array() const;
  const std::uint8_t* previous_level_array() const;
  const float* transition_array() const;
  // Each object's level for view class c (< max_view_classes; nullptr otherwise) this frame: the
  // finest of the class's views' (View), within its clamps. Indexed by ObjectId as level_array().
  const std::uint8_t* view_level_array(std::uint32_t view_class) const;
  const FrameStats& stats() const;
  const SchedulerConfig& config() const;

  // Bytes of tabulated-path tables held for profile index p (0 when not tabulated), and what this
  // profile would take under a configuration (before adding it): every view's with the bounds over
  // them (kAllViews, add_profile's), or one view's (make_tables(p, view)'s; 0 for a view out of range).
  std::size_t table_bytes(int profile) const;
  static std::size_t table_bytes(const Profile& profile, const SchedulerConfig& config, int view = kAllViews);

  // The speed at which a moving component of frequency f [cpd] is evaluated at least (the velocity
  // envelope of the Default model; 0 where the CSF already falls with speed) [deg/s].
  float envelope_speed(float frequency_cpd) const;

  // Recomputes one object for the current frame with full detail (allocation-free, not for every object).
  bool explain(ObjectId id, ObjectExplain* out) const;

  // Detail inside one object (acuity/clusters.hpp; docs/design.md section 6, "Cluster cuts"): after
  // begin_frame, the cut of hierarchy `h` for an object placed by `transform` (its sphere and group
  // spheres are the hierarchy's, in object units x scale) moving at `velocity` [m/s, world; nullptr:
  // still], seen by this frame's eyes and gaze under this configuration's model, params, quality q
  // and gaze handling (the perceptual rule's thresholds, evaluated exactly, whatever `rule` and
  // `evaluation` say). Per group and eye: the distance to the nearest point of its sphere, the
  // eccentricity of that point from the gaze (less gaze_uncertainty_deg; without a gaze, from the
  // no-gaze disc), band b's frequency loss.bands_cpod[b] / (the angle loss.diameter x scale
  // subtends there) [cpd], bands above the display's Nyquist frequency invisible (taken at the
  // sphere's point farthest off the view axis). A group is invisible when every band's lost contrast
  // is at most q x CT for both eyes; with loss per view cell (loss.view_directions), each eye reads
  // the cell it is in, seen from the group's centre in object space (a group hidden from there, or
  // seen face-on rather than at the silhouette, loses less). The loss carries no orientation, so a moving object is
  // evaluated at the least retinal speed over orientations, the drift floor, with the velocity
  // envelope (as the object rule treats a moving component at that speed); a still one (no motion
  // relative to an eye, no head rotation, no measured gaze motion) at the floor without it. So,
  // until the loss has orientations, motion never coarsens a cut. An eye inside a group's sphere
  // makes it visible (kFlagEyeInside).
  // The walk goes top down (groups in reverse order) and never evaluates a group below an invisible
  // one: a group is visible when its own test says so and every group holding a cluster it made is
  // visible, so visibility is monotone up the hierarchy whatever the model; a cluster is drawn when
  // the group that made it is invisible (or it is finest) and its own group is visible (or it is a
  // root): the cut is crack-free (tests/test_cluster_cut.cpp).
  // Writes the drawn cluster ids to `drawn` (group order, then roots); `scratch` holds one byte per
  // group (the caller's: calls may run concurrently on separate scratch, between begin_frame and
  // end_frame); on return with CutStatus::Ok, scratch[g] & 4 is set exactly when group g is visible
  // (its members, or finer, are drawn). Allocation-free, deterministic. Bad input falls back to the finest cut (CutStatus).
  // Not yet: tabulated thresholds (issue 48 item 3).
  CutResult select_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& transform,
                       const float velocity[3], std::span<std::uint8_t> scratch,
                       std::span<std::uint32_t> drawn) const;
  // The same with hysteresis and saccade gating per group, remembered in `memory` (one per group,
  // the caller's; empty: none, as above). Call it once per frame per object and memory: each call is
  // one frame's step of SchedulerConfig's timing (this frame's dt). A group refines (becomes visible)
  // at once; a visible group the walk reaches coarsens (becomes invisible, its made clusters drawn
  // instead of its members) when the object rule would let an object coarsen: its score has been
  // <= 1 - hysteresis_margin for the hysteresis and, with saccade gating, then a saccade or the
  // wait (CutResult::held counts the groups kept visible meanwhile, kFlagHeld). A score in
  // (1 - margin, 1] keeps a visible group visible and an invisible one invisible. A group below a
  // coarsened one is not reached and is remembered invisible, so the walk's monotonicity, and so
  // the cut's crack-freedom, hold as without memory. Invalid input draws the finest cut and
  // remembers every group visible (coarsening then waits again); BadHierarchy (memory given but
  // smaller than the groups, among the rest) leaves memory untouched; BufferTooSmall has stepped it.
  CutResult select_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& transform,
                       const float velocity[3], std::span<CutGroupMemory> memory,
                       std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn) const;
  // The same under a triangle budget (memory may be empty: none). When the cut (after hysteresis)
  // draws more than budget.triangles (> 0), it coarsens one group at a time, as the frame's budget
  // coarsens objects (Funkhouser & Sequin): of the visible groups none of whose members' makers is
  // visible (so only a whole group's members are replaced by the clusters it made, and the cut
  // stays crack-free), the one of least harm, its score (lost / (q CT), the largest over eyes and
  // bands, as explain_cut's) per triangle it saves (at least 1); ties go to the lower group. Until
  // the cut draws at most budget.triangles or no such group is left: a group an eye is inside (or
  // with a NaN loss; score +inf) is never coarsened, as the frame's budget never coarsens an
  // object an eye is inside, nor is invalid input's finest cut. CutResult::budget_coarsened counts
  // the groups, budget_forced those of a score > 1 (kFlagBudgetForced); memory remembers them
  // invisible (they refine at once when the budget allows). Needs h.made (cluster_made_index) and
  // budget.scratch (one per group, the caller's like scratch). A budget at or above the cut
  // changes nothing. Allocation-free, deterministic.
  CutResult select_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& transform,
                       const float velocity[3], std::span<CutGroupMemory> memory, const CutBudget& budget,
                       std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn) const;
  // Why select_cut decides as it does (for debugging, not every frame): for every group (out, one per
  // group) its score over both eyes with the limiting band, eye and their frequency, threshold,
  // distance and eccentricity, the same arithmetic as select_cut's; `visible` as select_cut without
  // memory would leave it. A cluster's maker (Cluster::refined) says why it is not finer, its group
  // why it is not coarser. Allocation-free; `scratch` as select_cut's. Returns select_cut's status
  // (out untouched unless Ok).
  CutStatus explain_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& transform,
                        const float velocity[3], std::span<std::uint8_t> scratch,
                        std::span<GroupExplain> out) const;

 private:
  friend class ProfileTables;
  struct Impl;  // every array and pass (scheduler/src/impl.hpp)
  std::unique_ptr<Impl> impl_;
};

// One profile's tables, made by Scheduler::make_tables() for Scheduler::install_tables(): movable,
// opaque.
class ProfileTables {
 public:
  ProfileTables();
  ~ProfileTables();
  ProfileTables(ProfileTables&&) noexcept;
  ProfileTables& operator=(ProfileTables&&) noexcept;
  explicit operator bool() const { return data_ != nullptr; }
  std::size_t bytes() const;  // what install_tables() adds to Scheduler::table_bytes()

 private:
  friend class Scheduler;
  struct Data;  // scheduler/src/tables.hpp
  std::unique_ptr<Data> data_;
};

}  // namespace acuity
