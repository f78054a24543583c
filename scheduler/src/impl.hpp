#pragma once
// The scheduler's implementation (scheduler/src only): Scheduler::Impl holds every array and runs every
// pass; the public Scheduler forwards each call to it (scheduler.cpp). Its parts are defined by
// concern: runtime_math.hpp (Precomputed), geometry.hpp (EyeCache, Sight, Block, Decisions),
// tables.hpp (ProfileCache, Probe), curves.hpp (Curves), memory.hpp (Memo, RestProbe).
#include "acuity/scheduler.hpp"

#include <algorithm>
#include <limits>

namespace acuity {
namespace internal {
struct AreaLaw;
}

struct Scheduler::Impl {
  // The work of the public calls (scheduler.hpp documents each; Scheduler forwards to these, and
  // reads the per-object arrays below for its accessors).
  explicit Impl(const SchedulerConfig& config);
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  void begin_frame(const Frame& frame);
  void update(std::uint32_t first, std::uint32_t count);
  void end_frame();
  // A profile's tables (tables.hpp). add_profile with tables false defers them; make_tables returns
  // false when there are none to make; install_tables moves them in.
  struct ProfileTableSets;
  int add_profile(const Profile& profile, bool tables = true);
  bool make_tables(int profile, int view, ProfileTableSets* out) const;
  bool install_tables(int profile, ProfileTableSets* sets);
  std::uint32_t wanted_tables(std::span<TablesWanted> out);
  std::size_t drop_idle_tables(std::uint32_t frames);
  void note_want(ObjectId id);  // an object's want_ into its profile's ProfileCache::wanted
  std::size_t table_bytes(int profile) const;
  static std::size_t table_bytes(const Profile& profile, const SchedulerConfig& config, int view);
  float envelope_speed(float frequency_cpd) const;
  ObjectId add_object(int profile, const ObjectTransform& transform);
  void set_transform(ObjectId id, const ObjectTransform& transform);
  void set_velocity(ObjectId id, const float velocity[3]);
  void set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level);
  void set_bias(ObjectId id, float quality_bias);
  void remove_object(ObjectId id);
  bool alive(ObjectId id) const { return id < config_.max_objects && profile_of_[id] >= 0; }
  const float* scores(ObjectId id) const;
  bool explain(ObjectId id, ObjectExplain* out) const;

  // ---- Internals ----
  struct ProfileCache;
  struct EyeCache;
  struct ViewCache;
  struct Precomputed;
  struct Curves;
  struct Sight;
  struct Block;
  struct Choice {
    std::uint8_t fine, coarse, flags;
  };  // coarsest level at score <= 1 and <= 1 - margin
  // Two eyes' choices of one object: the finer need wins.
  static Choice finer(const Choice& a, const Choice& b) {
    return {std::min(a.fine, b.fine), std::min(a.coarse, b.coarse),
            static_cast<std::uint8_t>(a.flags | b.flags)};
  }
  enum class Look : std::uint8_t { Ok, Invalid, Inside };
  bool perceptual() const {
    return config_.rule == SelectionRule::Perceptual || config_.rule == SelectionRule::Reddy;
  }
  void pause_rests(bool looked, std::uint32_t found);
  void look_block(const EyeCache& eye, std::uint32_t first, std::uint32_t count, Block* out) const;
  Look sight(ObjectId id, const EyeCache& eye, const Block& block, std::uint32_t j, Sight* out) const;
  void prefetch_views(ObjectId id, const Sight& s) const;
  void aim(ObjectId id, Sight* s) const;  // perceptual rules: the nearest view, the slip in its axes
  std::uint32_t aim(ObjectId id, const std::uint16_t* cand, Vec3 to_eye, Vec3 slip, float* vx,
                    float* vy) const;
  static const std::uint16_t* lookup_candidates(const Profile& p, const Block& b, std::uint32_t j);
  Choice evaluate(ObjectId id, Look look, const Sight& s, float* scores, ObjectExplain* explain) const;
  Choice choose_by_error(ObjectId id, const Sight& s) const;  // Distance, ScreenSize (explain)
  float error_threshold(float error_size, float focal_px) const;
  Choice choose_exact(ObjectId id, const Sight& s, float* scores,
                      ObjectExplain* explain) const;  // Perceptual, Reddy
  std::uint32_t exact_thresholds(const ProfileCache& pc, const Sight& s, float* ln_ct) const;
  bool uses_detail(const Profile& p) const;  // StelaCsf's perceptual rule on a profile with Detail
  // Whether SchedulerConfig::area_law applies to p's losses (under this scheduler's config, or c).
  bool area_law(const Profile& p) const { return area_law(p, config_); }
  static bool area_law(const Profile& p, const SchedulerConfig& c);
  // Rows per view and level of p's moving tables: 1 where every orientation reads the same loss
  // (the area law's pooled one), else one per orientation.
  static std::uint32_t moving_orientations(const Profile& p, const SchedulerConfig& c);
  void area_ks(ProfileCache& c) const;  // fills c.area_k (empty where it does not apply)
  void detail_thresholds(const ProfileCache& pc, const Sight& s, std::uint32_t k, std::uint32_t view,
                         const float* centre_ln_ct, std::uint32_t stride, float* ln_ct) const;
  void area_thresholds(const ProfileCache& pc, std::uint32_t k, std::uint32_t view, const float* weight,
                       const float* ln_ct, std::uint32_t rows, std::uint32_t stride, float* out) const;
  void band_thresholds(const float* bands, const float* ln_band, std::uint32_t B, float inv_diam,
                       float ln_diam, float nyquist_cpd, float e, float a, float v, bool moving,
                       float* row) const;
  // Cluster cuts (clusters.cpp; Scheduler::select_cut, explain_cut): one eye's score of one group
  // [ln lost / (q CT), max over bands, the loss of the view cell the eye is in when the loss has
  // cells; +inf visible at once], and the cut (explain: nullable, one per group, every group scored).
  struct CutObject;
  bool cut_object(const ClusterLoss& loss, const ObjectTransform& t, const float velocity[3],
                  CutObject* o) const;
  // The geometry of a run of consecutive groups seen from one eye (group_sights(): a loop over the
  // run that vectorises; the walk computes a run when it first needs one of its groups).
  struct GroupSights;
  void group_sights(std::uint32_t eye, const CutObject& o, const ClusterGroup* groups, std::size_t first,
                    std::size_t count, GroupSights* out) const;
  // One group's score from its sight `s` (entry j): every_band: the largest over bands even when
  // visible (else the first band above 0 ends it). *inside (nullable): whether the eye is inside (or
  // on) the group's sphere.
  float group_score(std::uint32_t eye, const CutObject& o, const GroupSights& s, std::uint32_t j,
                    std::size_t index, GroupExplain* explain, bool every_band = false,
                    bool* inside = nullptr) const;
  CutResult select_cut(const ClusterView& h, const ClusterLoss& loss, const ObjectTransform& transform,
                       const float velocity[3], std::span<CutGroupMemory> memory,
                       std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn, GroupExplain* explain,
                       const CutBudget* budget = nullptr) const;
  // select_cut's triangle budget (clusters.cpp): coarsens visible groups of the walk's state until
  // the cut draws at most budget.triangles (from `triangles`, what it draws now); the walk left each
  // visible group's score in budget.scratch[g].harm.
  void spend_cut_budget(const ClusterView& h, const CutBudget& budget, std::uint64_t triangles,
                        std::uint8_t* state, std::span<CutGroupMemory> memory, CutResult* res) const;
  // One frame of the wait to coarsen (SchedulerConfig's timing), the one arithmetic of settle()'s
  // objects and select_cut's groups. step() takes how long the coarser choice has been wanted (calm)
  // and waited for a saccade since the hysteresis was met (wait) before this frame, and gives both
  // with this frame counted and whether the coarser choice may apply now (ready). Plain arithmetic
  // and selects: settle()'s loop vectorises with it.
  struct CoarsenTiming {
    float hold_need, wait_need, both_need, hold_step, wait_step;
    std::uint32_t both_seconds, gate_open;
    struct Step {
      float calm, wait;
      std::uint32_t ready;
    };
    [[gnu::always_inline]] Step step(float calm, float wait) const {
      constexpr float kMost = std::numeric_limits<float>::max();  // sums stop here: +inf is never reached
      // Wanted this long, this frame included; the wait counts from the moment the hysteresis was
      // met (both in seconds: from the sum) or, in frames or after a frame-count hysteresis, from
      // the frame it was met.
      const float calm_now = std::min(calm + hold_step, kMost);
      const std::uint32_t settled = calm_now >= hold_need;
      const std::uint32_t was_settled = std::uint32_t(calm > 0.0f) & std::uint32_t(calm >= hold_need);
      const float wait_now = std::min(wait + (was_settled ? wait_step : 0.0f), kMost);
      // Masks, not a select on both_seconds: GCC vectorises no select between two comparisons.
      const std::uint32_t waited = (both_seconds & std::uint32_t(calm_now >= both_need)) |
                                   ((both_seconds ^ 1u) & std::uint32_t(wait_now >= wait_need));
      return {calm_now, wait_now, settled & (gate_open | waited)};
    }
  };
  // select_cut's hysteresis for one group the walk reached (clusters.cpp): whether it is visible.
  static bool remember_group(CutGroupMemory& m, bool visible, float score, const CoarsenTiming& timing,
                             float ln_margin, std::uint32_t* held);
  CoarsenTiming coarsen_timing() const {
    return {hold_need_,
            wait_need_,
            both_need_,
            hold_step_,
            wait_step_,
            std::uint32_t(both_seconds_),
            std::uint32_t(config_.saccade_speed <= 0 || saccade_)};
  }
  void explain_level(const ProfileCache& pc, std::uint32_t view, std::uint32_t k, const float* ln_ct,
                     std::uint32_t stride, float inv_diam, float ln_excess, LevelExplain* out) const;
  struct Probe;   // tabulated path: one object's table position
  struct Memo;    // tabulated path: per eye, each object's last decision made over whole cells
  struct Inputs;  // tabulated path: a block's table positions and memo hits
  void table_inputs(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                    const Memo& memo, bool use_memo, Inputs* out) const;
  // want: per object, 1 + the view whose tables it lacked (left as it was where none).
  void tabulate(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b, Memo& memo,
                Choice* out, float (*scores)[kMaxLevels], std::uint16_t* want) const;
  struct Tabulation;  // tabulate()'s passes: one block's state between them
  void tabulate_memos(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b,
                      const Memo& memo, bool scores, Tabulation& tb) const;
  void tabulate_rows(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b, Memo& memo,
                     Choice* out, float (*scores)[kMaxLevels], Tabulation& tb) const;
  void tabulate_any_view(std::uint32_t first, const Block& b, Memo& memo, Choice* out, Tabulation& tb) const;
  void tabulate_views(const EyeCache& eye, std::uint32_t first, std::uint32_t n, const Block& b, Memo& memo,
                      Choice* out, float (*scores)[kMaxLevels], std::uint16_t* want, Tabulation& tb) const;
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
  // The tables of profile c (its inputs, add_profile's) for views [first, first + count) into sets
  // (kTableSets), from curves_ and the configuration only: concurrent calls may build the tables of
  // several profiles or views at once.
  void build_tables(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t first,
                    std::uint32_t count) const;
  // knots: the area law's per level, view and band (Curves::kKnots each), null without it.
  void build_still(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set, float ln_q,
                   std::uint32_t w, std::uint32_t row, std::uint32_t k, const float* knots) const;
  void build_moving(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set, float ln_q,
                    std::uint32_t first, std::uint32_t count, const float* knots) const;
  void build_any_view(const ProfileCache& c, ProfileTableSets* sets, std::uint32_t set) const;
  // Moves sets' tables into c's (add_profile's, or install_tables' once its checks pass): each view's
  // rows after those c has, its slot set, and with the last view the bounds over every view.
  void take_tables(ProfileCache& c, ProfileTableSets* sets) const;
  void lower_speed_rows(const float* nodes, const float* ys, const internal::AreaLaw* laws,
                        const float* ln_band, std::uint32_t B, std::uint32_t T, float* lowers) const;
  struct Need;
  struct Lowering {
    float lower, upper;  // [ln deg] at a cell's lower and upper node
  };
  static Lowering least_lowering(const Need* needs, int count);
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
  static void pose_eye(const Eye& e, EyeCache* c);  // an eye's pose, projection and validity (no gaze)
  // Views beyond the eyes (views.cpp): the frame's views, then per block their levels per class.
  void begin_views(const Frame& frame);
  void decide_views(std::uint32_t first, std::uint32_t end);
  void view_levels(const ViewCache& v, std::uint32_t first, std::uint32_t count, std::uint8_t* out) const;
  std::uint8_t footprint_level(const ViewCache& v, ObjectId id) const;
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
  // bias_tables_ of an object of this bias (kExactBias where it has no tables).
  std::uint8_t bias_tables_of(float bias) const;

  SchedulerConfig config_;
  // This scheduler among every one the process made (ProfileTables names the one that made them: an
  // address could be a later scheduler's).
  const std::uint64_t serial_;
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
  // Per object, how long a coarser level has been wanted and waited for a saccade since the
  // hysteresis was met (settle()), in the units of hold_step_ and wait_step_.
  std::vector<float> calm_, wait_;
  std::vector<std::uint8_t> bias_tables_;  // index into table_bias_, kExactBias or kInvalidBias
  std::vector<std::uint16_t> want_;        // 1 + a view whose tables it lacked (0: none), for wanted_tables()
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
  std::vector<ViewCache> views_;  // [max_views]: this frame's, view_count_ of them
  std::uint32_t view_count_ = 0;
  std::vector<std::uint8_t> view_levels_;  // [max_view_classes][max_objects]
  float dt_ = 0;
  // The hysteresis and the wait for a saccade: their lengths (a little under the seconds, or the
  // frame counts; +inf: forever) and what each frame adds (its dt, or one frame). With the wait in
  // seconds and the hysteresis in seconds or none, the wait is over when wanted for their sum,
  // both_need_ (both_seconds_; else wait_ counts from the frame the hysteresis was met).
  float hold_need_ = 0, wait_need_ = 0, both_need_ = 0, hold_step_ = 1, wait_step_ = 1;
  bool both_seconds_ = false;
  bool saccade_ = false;
  std::uint32_t frame_ = 0;        // begin_frame's count
  bool resting_ = false;           // rests may be set this frame (a still eye)
  bool many_at_rest_ = false;      // an eighth of the objects were last frame
  bool looking_for_rest_ = false;  // objects are looked for at rest this frame
  // Rests no look finds cost without paying (pause_rests()): frames left before they are tried again,
  // and the pause after the next look that finds none.
  std::uint32_t rest_pause_ = 0, next_rest_pause_ = 0;
  // Every eye has stood still since frame still_since_ (eyes_still_): rests tried before it, which
  // failed for an eye that moved, are tried again at once rather than after Memo::kRetry frames.
  std::uint32_t still_since_ = 0;
  bool eyes_still_ = false;
  static constexpr std::uint32_t kFirstRestPause = 8, kLongestRestPause = 64;  // [frames]
  FrameStats stats_;
};

}  // namespace acuity
