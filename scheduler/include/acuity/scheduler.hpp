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
#include <vector>

#include "acuity/models.hpp"
#include "acuity/profile.hpp"

namespace acuity {

enum class SelectionRule : std::uint8_t {
  Perceptual,  // coarsest level whose lost contrast stays below q x threshold in every band (default)
  Reddy,       // coarsest level whose finer levels' smallest features all lie above H(v) M(e) [unverified]
  Distance,    // OpenSceneGraph-style: level k from distance >= distance_scale x d_k (baseline)
  ScreenSize,  // Unity-style screen-relative size: level k while its error covers <= pixel_error px (baseline)
};

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
  // Hysteresis and timing
  float hysteresis_margin = 0.0f;       // coarsening needs a score <= 1 - margin
  std::uint32_t hysteresis_frames = 0;  // ... on this many consecutive frames
  float saccade_speed = 0.0f;           // > 0: coarsen only while gaze speed exceeds it [deg/s]; during
                                        // such a saccade the eye counts as fixating (the level is seen
                                        // after it, so the saccade's retinal blur is not spent) ...
  std::uint32_t max_coarsen_wait = 30;  // ... or after waiting this many frames for a saccade
  float transition_seconds = 0.0f;      // cross-fade length reported by transition() [s]

  // Budget (Funkhouser & Sequin): 0 = none; else coarsen greedily by least harm per triangle saved
  // (a budget turns keep_scores on: harm is the next level's score)
  std::uint64_t triangle_budget = 0;

  // Baselines
  float distance_scale = 1.0f;  // Distance: d_k = geometric error k / tan(1 arcmin), times this
  float pixel_error = 1.0f;     // ScreenSize: allowed projected geometric error [px]

  bool keep_scores = false;  // keep every level's score for scores()
};

// Names used by the command line, Python and the C ABI's documentation: "perceptual", "reddy",
// "distance", "screen-size"; "tabulated", "exact". parse_* return false for an unknown name.
const char* to_string(SelectionRule rule);
const char* to_string(Evaluation evaluation);
bool parse_selection_rule(const char* name, SelectionRule* out);
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

struct Frame {
  Eye eyes[2];
  Gaze gaze[2];
  std::uint32_t eye_count = 1;  // 1 or 2
  float dt = 0;                 // since the previous frame [s]; 0 derives no velocity
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
  float score;        // max over bands and orientations of lost / (q CT); <= 1 is invisible
  std::uint8_t band;  // the limiting band and orientation
  std::uint8_t orientation;
  float frequency_cpd;  // that band's centre at the current distance
  float threshold;      // CT there
};

struct ObjectExplain {
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

// The tabulated path (Evaluation::Tabulated, the default for the perceptual rule). For each profile,
// view and level k, add_profile stores the largest angular size [ln deg] at which k's loss stays below
// q x threshold: still objects on a grid over eccentricity (one table per number of bands the display
// can show: the display's Nyquist limit is exact up to 3 bands cut), moving objects per orientation on
// a grid over eccentricity and that orientation's retinal speed. Beside them, per band count and
// eccentricity node, the least and the most of the still tables over every view (and the least of the
// still and slow ones): most objects are decided from those (over their eccentricity cell, else
// interpolated at their eccentricity) before their view is looked up, exactly as their own view's
// tables would decide. Per object and frame the work is the geometry, then one
// table read (decided over every view), or one per level (still) or per level and orientation
// (moving) through the object's view. A decision made over whole cells, or at the object's place in
// them (through its view: a still image's; over the quarters of its cells it lies in: a moving
// one's), is kept per object and eye (32 bytes each, allocated at creation) with what it stands
// under: the same eccentricity cell, table set, still or moving image and bands shown, and a size
// (at its place: and an eccentricity) clear of the bounds it compared; made through the object's
// view, also the same view (Max3: lookup cell) and, moving, the same cells (quarters) of
// eccentricity and of each orientation's speed (profiles of up to 16 orientations, 10 for
// quarters). Such a decision through the view also holds (40 bytes per object and eye) while the
// direction to the eye turns less than keeps its view, the retinal slip moves less than keeps its
// speed cells and the eccentricity stays in its moving cell, with the rotation unchanged: then the
// view is not looked up again. While those hold,
// the next frames take it without reading a table: the same decision, bit for bit (with keep_scores,
// or a triangle budget, every object reads its view's tables and nothing is kept). At rest: while
// neither the eye (no velocity, angular velocity or gaze velocity reported) nor the object moves
// (its transform set to other bits, its velocity or bias set), an object whose kept decision stands
// gets a rest (12 bytes per object and eye): how far the eye may move [m] and the gaze and head turn
// [deg] before any input the decision stands under could leave its bounds, each input computed as
// the frame loop computes it at the ends of its range and confirmed inside. Within it, later frames
// take the kept decision without the object's geometry (FrameStats::at_rest counts them); blocks of
// 64 in which more than 4 runs of objects are not at rest take the whole loop. Tables are
// conservative: a decision may be finer than Exact's, never coarser (tests/test_scheduler.cpp pins it
// and the agreement rate). A level's score in this mode is the ratio of the object's angular size to
// that largest invisible size (<= 1 invisible), so the budget, hysteresis margin and keep_scores work
// from the tables. update() runs each block of 64 objects as passes: the geometry, the lookup cells
// and the clamps/hysteresis as vectorised loops (branch-free; with GCC on x86-64 also compiled for
// AVX2, picked at load time, same bits); the decision over every view, then for the rest the view,
// slip and grid position and the decision through the view, as scalar passes over compact per-object
// probes, each prefetching the table rows the next reads so a block's cache misses overlap. A moving object reads its per-orientation rows only where the slow
// bound does not already pass. Every rule reads per-profile counts, triangles and thresholds from
// small arrays the scheduler owns (not the profile blob); Distance and ScreenSize compare distance /
// radius with per-level thresholds set at begin_frame and compute no angles; velocities are derived from
// positions only in blocks holding an object without a given velocity. Tables cover the models whose
// thresholds never fall with speed: Default, GeislerPerry and the Reddy step model (its kinked cutoff
// lowers the nodes by what interpolation rises above it, known in advance); KellyDaly (its band-pass
// CSF rises with speed at low frequencies) evaluates exactly. Tables are built for q, q x margin and each
// of SchedulerConfig::tabulated_biases; an object of any other bias evaluates exactly.
// Memory: table_bytes(); `acuity inspect` prints it for a profile.
class Scheduler {
 public:
  explicit Scheduler(const SchedulerConfig& config);
  ~Scheduler();
  Scheduler(const Scheduler&) = delete;
  Scheduler& operator=(const Scheduler&) = delete;

  // Registers a profile (its bytes must outlive the scheduler). Returns its index, or -1 when full.
  int add_profile(const Profile& profile);

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

  std::uint32_t object_capacity() const { return config_.max_objects; }
  bool alive(ObjectId id) const { return id < config_.max_objects && profile_of_[id] >= 0; }
  std::uint8_t level(ObjectId id) const { return level_[id]; }
  std::uint8_t flags(ObjectId id) const { return flags_[id]; }
  // Cross-fade: the previous level and how far the fade to the current one is (1 = done).
  std::uint8_t previous_level(ObjectId id) const { return from_level_[id]; }
  float transition(ObjectId id) const { return fade_[id]; }
  // Every level's score this frame (needs keep_scores); nullptr otherwise.
  const float* scores(ObjectId id) const;
  const FrameStats& stats() const { return stats_; }
  const SchedulerConfig& config() const { return config_; }

  // Bytes of tabulated-path tables held for profile index p (0 when not tabulated), and what a
  // profile with this meta would take under a configuration (before adding it).
  std::size_t table_bytes(int profile) const;
  static std::size_t table_bytes(const ProfileMeta& meta, const SchedulerConfig& config);

  // The speed at which a moving component of frequency f [cpd] is evaluated at least (the velocity
  // envelope of the Default model; 0 where the CSF already falls with speed) [deg/s].
  float envelope_speed(float frequency_cpd) const;

  // Recomputes one object for the current frame with full detail (allocation-free, not for every object).
  bool explain(ObjectId id, ObjectExplain* out) const;

 private:
  struct ProfileCache;
  struct EyeCache;
  struct Precomputed;
  struct Curves;
  struct Sight;
  struct Block;
  struct Choice {
    std::uint8_t fine, coarse, flags;
  };  // coarsest level at score <= 1 and <= 1 - margin
  enum class Look : std::uint8_t { Ok, Invalid, Inside };
  bool perceptual() const {
    return config_.rule == SelectionRule::Perceptual || config_.rule == SelectionRule::Reddy;
  }
  void look_block(const EyeCache& eye, std::uint32_t first, std::uint32_t count, Block* out) const;
  Look sight(ObjectId id, const EyeCache& eye, const Block& block, std::uint32_t j, Sight* out) const;
  void prefetch_views(ObjectId id, const Sight& s) const;
  void aim(ObjectId id, Sight* s) const;  // perceptual rules: the nearest view, the slip in its axes
  Choice evaluate(ObjectId id, Look look, const Sight& s, float* scores, ObjectExplain* explain) const;
  Choice choose_by_error(ObjectId id, const Sight& s) const;  // Distance, ScreenSize (explain)
  float error_threshold(float error_size, float focal_px) const;
  Choice choose_exact(ObjectId id, const Sight& s, float* scores,
                      ObjectExplain* explain) const;  // Perceptual, Reddy
  std::uint32_t exact_thresholds(const ProfileCache& pc, const Sight& s, float* ln_ct) const;
  void explain_level(const ProfileCache& pc, std::uint32_t view, std::uint32_t k, const float* ln_ct,
                     std::uint32_t stride, float inv_diam, float ln_excess, LevelExplain* out) const;
  struct Probe;   // tabulated path: one object's table position
  struct Memo;    // tabulated path: per eye, each object's last decision made over whole cells
  struct Inputs;  // tabulated path: a block's table positions and memo hits
  void table_inputs(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                    const Memo& memo, bool use_memo, Inputs* out) const;
  void tabulate(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b, Memo& memo,
                Choice* out, float (*scores)[kMaxLevels]) const;
  struct Tabulation;  // tabulate()'s passes: one block's state between them
  void tabulate_memos(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                      const Memo& memo, bool scores, Tabulation& tb) const;
  void tabulate_rows(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                     const Memo& memo, Choice* out, float (*scores)[kMaxLevels], Tabulation& tb) const;
  void tabulate_any_view(std::uint32_t first, const Block& b, Memo& memo, Choice* out, Tabulation& tb) const;
  void tabulate_views(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b, Memo& memo,
                      Tabulation& tb) const;
  void tabulate_through_view(std::uint32_t first, const Block& b, Memo& memo, Choice* out,
                             float (*scores)[kMaxLevels], Tabulation& tb) const;
  Choice table_choice(const ProfileCache& pc, float e, Probe& o, float* scores) const;
  static int any_view_level(const std::int16_t* row, std::uint32_t L, std::int32_t x, bool still,
                            std::int32_t* lo, std::int32_t* hi);
  static int any_view_level_at(const std::int16_t* row, std::uint32_t L, float x, float w, bool still);
  void hold_view(Memo& memo, ObjectId id, const ProfileCache& pc, const Probe& o, const std::uint16_t* cand,
                 const Block& b, std::uint32_t j, bool quartered, bool still) const;
  static int view_cell_level(const ProfileCache& pc, const Probe& o, std::int32_t x, int set, bool quartered,
                             std::int32_t* lo, std::int32_t* hi);
  static const std::int16_t* any_view_row(const ProfileCache& pc, std::uint32_t L, std::uint32_t bands,
                                          std::uint32_t ec, int set);
  void speed_cells(const ProfileCache& pc, float e, Probe* o) const;
  void build_curves();  // at creation
  void build_tables(ProfileCache& c) const;
  void build_still(ProfileCache& c, std::uint32_t set, float ln_q, std::uint32_t w, std::uint32_t k) const;
  void build_moving(ProfileCache& c, std::uint32_t set, float ln_q, std::uint32_t w, std::uint32_t k) const;
  void build_any_view(ProfileCache& c, std::uint32_t set) const;
  // Whether a configuration's perceptual rule reads tables: the models whose thresholds never fall
  // with speed (see "The tabulated path").
  static bool tabulated(const SchedulerConfig& c) {
    return c.rule == SelectionRule::Perceptual && c.evaluation == Evaluation::Tabulated &&
           (c.model == ThresholdModel::Default || c.model == ThresholdModel::GeislerPerry ||
            c.model == ThresholdModel::Reddy);
  }
  bool tabulated() const { return tabulated(config_); }
  static constexpr std::uint32_t kBlock = 64;  // objects per pass of the frame loop
  struct Decisions;                            // one block's choices, both eyes combined
  void derive_velocities(std::uint32_t first, std::uint32_t count);
  void prefetch_objects(std::uint32_t first) const;  // a block's per-object arrays, ahead of its turn
  void prefetch_holds(std::uint32_t first) const;    // a block's holds in use, a block ahead
  void choose_perceptual(std::uint32_t first, std::uint32_t count, const Look (*looks)[kBlock],
                         const Sight (*sights)[kBlock], Decisions* out);
  void choose_by_error(std::uint32_t first, std::uint32_t count, const Block* blocks, Decisions* out);
  void choose_tabulated(std::uint32_t first, std::uint32_t count, const Block* blocks, Decisions* out);
  void settle(std::uint32_t first, std::uint32_t count, const Decisions& d);  // clamps, hysteresis
  std::uint32_t count_flags(std::uint32_t first, std::uint32_t count, FrameStats* st) const;  // end_frame's
  // At rest (the tabulated path, a still eye): objects decided from their memos without geometry.
  struct RestProbe;
  // A block with more runs of objects not at rest than this, or more such objects, takes the whole
  // frame loop (rest_mask() returns false).
  static constexpr std::uint32_t kMostRestlessRuns = 4, kMostRestless = 16;
  bool rest_mask(std::uint32_t first, std::uint32_t count, std::uint32_t* at_rest) const;
  void prefetch_restless(std::uint32_t first, std::uint32_t count, const std::uint32_t* at_rest) const;
  void decide_at_rest(std::uint32_t first, std::uint32_t count, const std::uint32_t* at_rest, Decisions* out);
  bool stands_at_rest(const Memo& memo, ObjectId id, const RestProbe& h, float m, float t) const;
  void set_rest(const EyeCache& eye, Memo& memo, ObjectId id, const Block& b, std::uint32_t j) const;
  void end_rests(ObjectId id);
  void apply_budget();
  std::uint8_t bias_tables_of(float bias) const;  // bias_tables_ of an object of this bias

  SchedulerConfig config_;
  std::vector<ProfileCache> profiles_;
  std::uint32_t profile_count_ = 0;
  // Per profile, what every object reads, in small arrays owned here (not the profile blob):
  std::vector<std::uint8_t> level_count_;  // [max_profiles]
  std::vector<std::uint32_t> triangles_;   // [max_profiles][kMaxLevels]
  std::uint64_t drawn_triangles_ = 0;      // over the live objects at their drawn levels (level_)
  std::vector<float> error_size_;          // [max_profiles][kMaxLevels]: 2 x geometric error
  std::vector<float> error_threshold_[2];  // per eye, each frame: level k's least distance /
                                           // radius (Distance, ScreenSize); +inf past K - 1
  std::vector<float> band_frequency_;      // [max_profiles][kMaxBands]: band centres [cpod], +inf past B
  std::uint32_t max_level_count_ = 1;      // the largest K added
  std::uint32_t max_band_count_ = 0;       // the largest B added
  // Objects, structure of arrays: one array per component, so the frame loop vectorises.
  std::vector<int> profile_of_;  // -1: free slot
  std::vector<double> position_[3], previous_position_[3];
  std::vector<float> rotation_[4], velocity_[3], bias_;
  std::vector<float> sphere_[4];  // the profile's bounding sphere (centre, radius) x the object's scale
  std::vector<std::uint8_t> explicit_velocity_, fresh_, min_level_, max_level_, flags_;
  std::vector<std::uint8_t> chosen_;              // perceptual choice after hysteresis (before the budget)
  std::vector<std::uint8_t> next_;                // this frame's level after the budget
  std::vector<std::uint8_t> level_, from_level_;  // drawn level and the one it fades from
  std::vector<std::uint32_t> calm_frames_, wait_frames_;
  std::vector<std::uint8_t> bias_tables_;  // index into table_bias_, kExactBias or kInvalidBias
  std::vector<float> fade_, scores_;
  std::vector<std::uint8_t> rest_;  // 1: decided at rest this frame
  std::vector<std::uint32_t> free_list_;
  std::vector<std::uint32_t> heap_;  // budget pass
  // Frame state.
  std::unique_ptr<Precomputed> pre_;                    // model constants and the velocity envelope
  std::unique_ptr<Curves> curves_;                      // tabulated path: threshold curves on the table grid
  std::unique_ptr<Memo[]> memos_;                       // tabulated path: [2], one per eye
  float table_bias_[1 + kMaxTabulatedBiases] = {1.0f};  // the biases with tables: 1, then the config's
  std::uint32_t table_bias_count_ = 1;
  std::vector<EyeCache> eyes_;
  std::uint32_t eye_count_ = 0;
  float dt_ = 0;
  bool saccade_ = false;
  std::uint32_t frame_ = 0;        // begin_frame's count
  bool resting_ = false;           // rests may be set this frame (a still eye)
  bool many_at_rest_ = false;      // an eighth of the objects were last frame
  bool looking_for_rest_ = false;  // objects are looked for at rest this frame
  FrameStats stats_;
};

}  // namespace acuity
