// Per-frame LOD selection. See acuity/scheduler.hpp for the contract.
//
// The perceptual rule, per object and eye:
//   distance d, angular diameter D = 2 asin(r / d), eccentricity e from the gaze to the sphere,
//   image-plane angular velocity -> retinal velocity (Daly's pursuit or measured gaze), projected
//   onto each profile orientation t: v_t = |v_R . w_t| floored at the drift;
//   per band b: f = f_b / D [cpd]; ln CT(t, b) from the threshold model (bands above the display's
//   Nyquist frequency are invisible); level k's score = max_tb lost_k / (q CT).
// For the Default model, ln CT is split into per-orientation terms (one log10 and one log per
// orientation, once per frame for static objects) and per-band multiply-adds, using
//   ln S(f, v) = A(v) + 2 ln(2 pi c1 f) - b(v) f  above the peak f_p(v) = 2 / b(v), plateau below.
//
// This file: creation, profiles, objects, explain() and the names of rules. The frame loop is
// frame_loop.cpp; the choosers choose_*.cpp and tabulated.cpp; the memory memory.cpp.
#include "acuity/scheduler.hpp"

#include <atomic>

#include "curves.hpp"
#include "memory.hpp"

namespace acuity {

namespace {
// A wait as settle() compares it (SchedulerConfig's timing): seconds > 0, less the relative room of
// a float sum of many dt; else the frame count, at most 2^24 (a float counts frames exactly so far).
float timing_need(float seconds, std::uint32_t frames) {
  if (seconds > 0) return seconds * (1.0f - 1e-4f);
  return static_cast<float>(std::min<std::uint32_t>(frames, 1u << 24));
}
std::uint64_t next_serial() {
  static std::atomic<std::uint64_t> made{0};
  return ++made;
}
}  // namespace

Scheduler::Impl::Impl(const SchedulerConfig& config) : config_(config), serial_(next_serial()) {
  if (config_.triangle_budget > 0) config_.keep_scores = true;  // the budget pass needs them
  const std::size_t n = config_.max_objects;
  profiles_.resize(config_.max_profiles);
  profile_of_.assign(n, -1);
  for (int k = 0; k < 3; ++k) {
    position_[k].assign(n, 0.0);
    previous_position_[k].assign(n, 0.0);
    velocity_[k].assign(n, 0.0f);
  }
  for (int k = 0; k < 4; ++k) {
    rotation_[k].assign(n, k == 3 ? 1.0f : 0.0f);
    sphere_[k].assign(n, 0.0f);
  }
  bias_.assign(n, 1.0f);
  bias_tables_.assign(n, 0);
  want_.assign(n, 0);
  table_bias_count_ = table_biases(config_, table_bias_);
  explicit_velocity_.assign(n, 0);
  fresh_.assign(n, 0);
  min_level_.assign(n, 0);
  max_level_.assign(n, 255);
  chosen_.assign(n, 0);
  next_.assign(n, 0);
  level_.assign(n, 0);
  from_level_.assign(n, 0);
  flags_.assign(n, 0);
  calm_.assign(n, 0.0f);
  wait_.assign(n, 0.0f);
  // The wait in seconds counts from the moment the hysteresis was met: one in seconds, or none (a
  // frame count of 0 or 1, met at once) is a moment, and then the two are one sum of dt.
  const bool hold_seconds = config_.hysteresis_seconds > 0;
  both_seconds_ = config_.max_coarsen_wait_seconds > 0 && (hold_seconds || config_.hysteresis_frames <= 1);
  hold_need_ = both_seconds_ && !hold_seconds
                   ? 0.0f
                   : timing_need(config_.hysteresis_seconds, config_.hysteresis_frames);
  wait_need_ = timing_need(config_.max_coarsen_wait_seconds, config_.max_coarsen_wait);
  both_need_ =
      timing_need((hold_seconds ? config_.hysteresis_seconds : 0.0f) + config_.max_coarsen_wait_seconds, 0);
  fade_.assign(n, 1.0f);
  rest_.assign(n, 0);
  if (config_.keep_scores) scores_.assign(n * kMaxLevels, 0.0f);
  free_list_.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) free_list_.push_back(static_cast<std::uint32_t>(n - 1 - i));
  heap_.reserve(n);
  eyes_.resize(2);
  views_.resize(config_.max_views);
  view_levels_.assign(std::size_t(config_.max_view_classes) * n, 0);
  const std::size_t slots = std::size_t(config_.max_profiles) * kMaxLevels;
  level_count_.assign(config_.max_profiles, 1);
  band_frequency_.assign(std::size_t(config_.max_profiles) * kMaxBands, kInf);
  triangles_.assign(slots, 0);
  error_size_.assign(slots, 0.0f);
  for (std::vector<float>& t : error_threshold_) t.assign(slots, kInf);
  pre_ = std::make_unique<Precomputed>();
  Precomputed& pre = *pre_;
  pre.daly = daly_constants(config_.params);
  const bool daly_model =
      config_.model == ThresholdModel::Default || config_.model == ThresholdModel::KellyDaly;
  pre.floor_velocity = daly_model ? pre.daly.v_floor : static_cast<float>(config_.params.drift);
  // Reddy's H(v) is flat up to 0.825 deg/s, so its speed grid may start at the default drift whatever
  // the configured one (a floor near 0 would crowd the grid's octaves below 1 deg/s); the exact
  // path's speeds are floored there too, which changes no threshold, H being flat there.
  if (config_.model == ThresholdModel::Reddy)
    pre.floor_velocity = std::max(pre.floor_velocity, static_cast<float>(ModelParams{}.drift));
  pre.static_terms = velocity_terms(std::max(pre.floor_velocity, 1e-3f), pre.daly);
  pre.ln_quality = std::log(config_.quality);
  pre.ln_margin = std::log(std::max(1e-6f, 1.0f - config_.hysteresis_margin));
  pre.ecc_slope = static_cast<float>(config_.params.alpha / config_.params.e2);
  pre.distance_per_error = config_.distance_scale / std::tan(kRad / 60.0f);
  pre.speed_offset = 2.0f / pre.daly.c2;
  for (int i = 0; i < Precomputed::kTermsSize; ++i)
    pre.terms[i] = velocity_terms(
        std::exp(Precomputed::kTermsLnV0 + (Precomputed::kTermsLnV1 - Precomputed::kTermsLnV0) * float(i) /
                                               float(Precomputed::kTermsSize - 1)),
        pre.daly);
  const double step = (kEnvelopeLnF1 - kEnvelopeLnF0) / (kEnvelopeSize - 1);
  double previous = argmax_speed(std::exp(kEnvelopeLnF0), config_.params);
  for (int j = 0; j < kEnvelopeSize; ++j) {
    const double ln_f = kEnvelopeLnF0 + step * j;
    const double mid = argmax_speed(std::exp(ln_f + 0.5 * step), config_.params);
    const double next = argmax_speed(std::exp(ln_f + step), config_.params);
    const double u = std::max({previous, mid, next}) * 1.02;  // the interval's largest, plus a step
    pre_->upper[j] = u <= config_.params.drift * 1.02 ? 0.0f : float(u);
    if (pre_->upper[j] > 0) pre_->upper_terms[j] = velocity_terms(pre_->upper[j], pre_->daly);
    pre_->largest = std::max(pre_->largest, pre_->upper[j]);
    previous = next;
  }
  if (tabulated()) {
    memos_ = std::unique_ptr<Memo[]>(new Memo[2]{Memo(n), Memo(n)});
    build_curves();
  }
}

bool Scheduler::Impl::area_law(const Profile& p, const SchedulerConfig& c) {
  return c.area_law && (p.pooled || p.detail) && c.rule == SelectionRule::Perceptual &&
         (c.model == ThresholdModel::Default || c.model == ThresholdModel::GeislerPerry ||
          c.model == ThresholdModel::KellyDaly ||
          (c.model == ThresholdModel::StelaCsf && p.pooled && std::isinf(c.params.area)));
}

std::uint32_t Scheduler::Impl::moving_orientations(const Profile& p, const SchedulerConfig& c) {
  return area_law(p, c) ? 1u : p.meta.orientation_count;  // area_ks() gives every orientation the band's L
}

// With the area law (area_law()) a band's loss is read as the eye pools it: the energy over the
// orientations at each point, and that energy's extent. The Pooled section holds exactly that per
// level, view and band (its peak L and extent A). A profile with Detail but without Pooled gives a
// bound from each orientation channel's peak c_t and extent a_t: L = sqrt(sum_t c_t^2) is at least
// the pooled peak sqrt(max_x sum_t c_t(x)^2), and A = sum_t a_t c_t^2 / max_t c_t^2 at least its
// extent (the energy over its peak, which is >= max_t c_t^2), so L / sqrt(1 + A_c / A) bounds the
// pooled band's response (it reads up to about sqrt(T) high where the orientations' peaks lie
// apart). Every orientation of the band then reads L (a moving object's row t at its own threshold:
// the bound at the orientation the motion blurs least), and k = a0 / (A c^2) (Curves::area_term()).
void Scheduler::Impl::area_ks(ProfileCache& c) const {
  c.area_k.clear();
  const Profile& p = c.profile;
  if (!area_law(p)) return;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  const auto a0 = static_cast<double>(config_.params.stela.a0);
  c.area_k.assign(std::size_t(K - 1) * V * B, 0.0f);
  for (std::size_t kv = 0; kv < std::size_t(K - 1) * V; ++kv)
    for (std::uint32_t b = 0; b < B; ++b) {
      double energy = 0, area = 0;  // L^2 and A
      if (p.pooled) {
        const ProfilePooled& e = p.pooled[kv * B + b];
        energy = double(e.lost) * e.lost;
        area = std::exp2(-0.125 * e.area_code);
      } else {
        double spread = 0, top = 0;  // sum_t a_t c_t^2, max_t c_t^2
        for (std::uint32_t t = 0; t < T; ++t) {
          const std::size_t i = (kv * T + t) * B + b;
          const double e = double(p.lost[i]) * p.lost[i];
          energy += e;
          spread += e * detail_area(p.detail[i]);
          top = std::max(top, e);
        }
        area = top > 0 ? spread / top : 0;
      }
      const float ln_l = energy > 0 ? float(0.5 * std::log(energy)) : -kInf;
      const float k = energy > 0 ? float(a0 / (double(p.bands[b]) * p.bands[b] * area)) : 0.0f;
      c.ln_lost_any[kv * B + b] = ln_l;
      c.area_k[kv * B + b] = k;
      for (std::uint32_t t = 0; t < T; ++t) c.ln_lost[(kv * T + t) * B + b] = ln_l;
    }
}

float Scheduler::Impl::envelope_speed(float frequency_cpd) const {
  return pre_->speed_at(std::log(frequency_cpd));
}

int Scheduler::Impl::add_profile(const Profile& p, bool tables) {
  if (profile_count_ >= config_.max_profiles) return -1;
  ProfileCache& c = profiles_[profile_count_];
  c.profile = p;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  c.ln_lost.resize(std::size_t(K - 1) * V * T * B);
  for (std::size_t i = 0; i < c.ln_lost.size(); ++i)
    c.ln_lost[i] = p.lost[i] > 0 ? std::log(p.lost[i]) : -kInf;
  c.ln_lost_any.assign(std::size_t(K - 1) * V * B, -kInf);
  for (std::size_t kv = 0; kv < std::size_t(K - 1) * V; ++kv)
    for (std::uint32_t t = 0; t < T; ++t)
      for (std::uint32_t b = 0; b < B; ++b)
        c.ln_lost_any[kv * B + b] = std::max(c.ln_lost_any[kv * B + b], c.ln_lost[(kv * T + t) * B + b]);
  c.ln_band.resize(B);
  for (std::uint32_t b = 0; b < B; ++b) c.ln_band[b] = std::log(p.bands[b]);
  area_ks(c);
  c.moving_orientations = moving_orientations(p, config_);
  c.cos_t.resize(T);
  c.sin_t.resize(T);
  for (std::uint32_t t = 0; t < T; ++t) {
    c.cos_t[t] = std::cos(p.orientations[t] * kRad);
    c.sin_t[t] = std::sin(p.orientations[t] * kRad);
  }
  c.view_right.resize(3 * std::size_t(V));
  for (std::uint32_t v = 0; v < V; ++v) {
    const Vec3 r = cross(-1.0f * load(p.views[v].direction), load(p.views[v].up));
    c.view_right[3 * v] = r.x;
    c.view_right[3 * v + 1] = r.y;
    c.view_right[3 * v + 2] = r.z;
  }
  c.slot.assign(V, ProfileCache::kNoRow);
  c.wanted.assign(V, 0);
  c.read_frame = std::make_unique<std::atomic<std::uint32_t>[]>(V);
  if (curves_ && tables) {
    ProfileTableSets sets;
    build_tables(c, &sets, 0, V);
    take_tables(c, &sets);
  }
  level_count_[profile_count_] = static_cast<std::uint8_t>(K);
  std::copy(p.bands, p.bands + B, &band_frequency_[std::size_t(profile_count_) * kMaxBands]);
  max_band_count_ = std::max(max_band_count_, B);
  max_level_count_ = std::max(max_level_count_, K);
  for (std::uint32_t k = 0; k < K; ++k) {
    triangles_[std::size_t(profile_count_) * kMaxLevels + k] = p.levels[k].triangles;
    error_size_[std::size_t(profile_count_) * kMaxLevels + k] = 2.0f * p.levels[k].geometric_error;
  }
  return static_cast<int>(profile_count_++);
}

ObjectId Scheduler::Impl::add_object(int profile, const ObjectTransform& t) {
  if (profile < 0 || profile >= static_cast<int>(profile_count_) || free_list_.empty()) return kInvalidObject;
  const ObjectId id = free_list_.back();
  free_list_.pop_back();
  profile_of_[id] = profile;
  set_transform(id, t);
  for (int k = 0; k < 3; ++k) {
    previous_position_[k][id] = t.position[k];
    velocity_[k][id] = 0;
  }
  explicit_velocity_[id] = 0;
  fresh_[id] = 1;
  min_level_[id] = 0;
  max_level_[id] = static_cast<std::uint8_t>(level_count_[profile] - 1);
  bias_[id] = 1.0f;
  bias_tables_[id] = bias_tables_of(1.0f);
  want_[id] = 0;
  level_[id] = from_level_[id] = chosen_[id] = next_[id] = std::min<std::uint8_t>(
      config_.fallback_level, static_cast<std::uint8_t>(profiles_[profile].profile.meta.level_count - 1));
  drawn_triangles_ += triangles_[std::size_t(profile) * kMaxLevels + level_[id]];
  flags_[id] = 0;
  calm_[id] = wait_[id] = 0.0f;
  fade_[id] = 1.0f;
  for (std::uint32_t e = 0; memos_ && e < 2; ++e) memos_[e].forget(id);  // another profile's, maybe
  end_rests(id);
  return id;
}

void Scheduler::Impl::remove_object(ObjectId id) {
  if (!alive(id)) return;
  note_want(id);
  drawn_triangles_ -= triangles_[std::size_t(profile_of_[id]) * kMaxLevels + level_[id]];
  profile_of_[id] = -1;
  sphere_[3][id] = 0.0f;   // a free slot looks invalid to the frame loop
  next_[id] = level_[id];  // and counts nothing in end_frame (the frame loop keeps a free slot's state)
  flags_[id] = 0;
  rest_[id] = 0;
  end_rests(id);
  free_list_.push_back(id);
}

void Scheduler::Impl::set_transform(ObjectId id, const ObjectTransform& t) {
  if (!alive(id)) return;
  // The frame reads the sphere scaled (the same products it would form): one array fewer per object.
  const float* sphere = profiles_[profile_of_[id]].profile.meta.sphere;
  bool same = true;  // the same bits: an object set where it was keeps its rests
  for (int k = 0; k < 3; ++k) {
    same = same && std::memcmp(&position_[k][id], &t.position[k], sizeof(double)) == 0;
    position_[k][id] = t.position[k];
  }
  bool same_rotation = true;  // and one not turned, its holds
  for (int k = 0; k < 4; ++k) {
    const float scaled = t.scale * sphere[k];
    same_rotation = same_rotation && std::memcmp(&rotation_[k][id], &t.rotation[k], sizeof(float)) == 0;
    same = same && std::memcmp(&sphere_[k][id], &scaled, sizeof(float)) == 0;
    rotation_[k][id] = t.rotation[k];
    sphere_[k][id] = scaled;
  }
  if (!same || !same_rotation) end_rests(id);
  if (!same_rotation && memos_)
    for (int i = 0; i < 2; ++i) memos_[i].end_hold(id);
}

void Scheduler::Impl::set_velocity(ObjectId id, const float v[3]) {
  if (!alive(id)) return;
  for (int k = 0; k < 3; ++k) velocity_[k][id] = v[k];
  explicit_velocity_[id] = 1;
  end_rests(id);
}

void Scheduler::Impl::set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level) {
  if (!alive(id)) return;
  min_level_[id] = min_level;
  max_level_[id] =
      std::min(std::max(min_level, max_level), static_cast<std::uint8_t>(level_count_[profile_of_[id]] - 1));
}

void Scheduler::Impl::set_bias(ObjectId id, float quality_bias) {
  if (!alive(id)) return;
  bias_[id] = quality_bias;
  bias_tables_[id] = bias_tables_of(quality_bias);
  end_rests(id);
}

// Its own tables, if it is a tabulated bias; else the exact path (rounding it to a tabulated bias
// would drop what the engine asked for). The frame loop tests an object's bias here, not bias_.
std::uint8_t Scheduler::Impl::bias_tables_of(float bias) const {
  const float q = config_.quality * bias;
  if (!(std::isfinite(q) && q > 0.0f)) return kInvalidBias;
  const float* tabulated = std::find(table_bias_, table_bias_ + table_bias_count_, bias);
  return tabulated == table_bias_ + table_bias_count_ ? kExactBias
                                                      : static_cast<std::uint8_t>(tabulated - table_bias_);
}

const float* Scheduler::Impl::scores(ObjectId id) const {
  return config_.keep_scores && alive(id) ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
}

bool Scheduler::Impl::explain(ObjectId id, ObjectExplain* out) const {
  if (!alive(id) || !out) return false;
  *out = ObjectExplain{};
  // The eye that needs the finer level is the one that decides.
  std::uint8_t best = 255;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    ObjectExplain tmp{};
    Block block;
    look_block(eyes_[i], id, 1, &block);
    Sight s;
    const Look look = sight(id, eyes_[i], block, 0, &s);
    if (look == Look::Ok && perceptual()) aim(id, &s);
    const Choice c = evaluate(id, look, s, nullptr, &tmp);
    if (c.fine < best) {
      best = c.fine;
      *out = tmp;
    }
  }
  out->level = level_[id];
  out->level_count = static_cast<std::uint8_t>(profiles_[profile_of_[id]].profile.meta.level_count);
  return true;
}

namespace {
constexpr RuleInfo kRules[] = {
    {SelectionRule::Perceptual, "perceptual",
     "coarsest level whose lost contrast stays below q x threshold in every band (default)"},
    {SelectionRule::Reddy, "reddy",
     "coarsest level whose finer levels' smallest features all lie above H(v) M(e) [unverified]"},
    {SelectionRule::Distance, "distance",
     "OpenSceneGraph-style: level k from distance >= distance_scale x d_k"},
    {SelectionRule::ScreenSize, "screen-size",
     "Unity-style screen-relative size: level k while its error covers <= pixel_error px"},
};
constexpr bool in_enum_order() {
  for (std::size_t i = 0; i < std::size(kRules); ++i)
    if (static_cast<std::size_t>(kRules[i].rule) != i) return false;
  return true;
}
static_assert(in_enum_order(), "kRules lists the rules in SelectionRule order");
constexpr const char* kEvaluationNames[] = {"tabulated", "exact"};  // Evaluation order
}  // namespace

std::span<const RuleInfo> selection_rules() { return kRules; }
const char* to_string(SelectionRule rule) {
  const auto i = static_cast<std::size_t>(rule);
  return i < std::size(kRules) ? kRules[i].name : "unknown";
}
const char* to_string(Evaluation evaluation) {
  const auto i = static_cast<std::size_t>(evaluation);
  return i < std::size(kEvaluationNames) ? kEvaluationNames[i] : "unknown";
}
bool parse_evaluation(const char* name, Evaluation* out) {
  if (!name) return false;
  for (std::size_t i = 0; i < std::size(kEvaluationNames); ++i)
    if (std::strcmp(name, kEvaluationNames[i]) == 0) {
      *out = static_cast<Evaluation>(i);
      return true;
    }
  return false;
}

// ---- The public face: every call forwards to the implementation ----------------------------------

Scheduler::Scheduler(const SchedulerConfig& config) : impl_(std::make_unique<Impl>(config)) {}
Scheduler::~Scheduler() = default;
int Scheduler::add_profile(const Profile& profile) { return impl_->add_profile(profile); }
int Scheduler::add_profile_deferred(const Profile& profile) { return impl_->add_profile(profile, false); }
ProfileTables Scheduler::make_tables(int profile, int view) const {
  ProfileTables out;
  Impl::ProfileTableSets tables;
  if (impl_->make_tables(profile, view, &tables))
    out.data_ = std::make_unique<ProfileTables::Data>(
        ProfileTables::Data{impl_->serial_, profile, std::move(tables)});
  return out;
}
bool Scheduler::install_tables(int profile, ProfileTables&& tables) {
  if (!tables.data_ || tables.data_->scheduler != impl_->serial_ || tables.data_->profile != profile)
    return false;
  if (!impl_->install_tables(profile, &tables.data_->tables)) return false;
  tables.data_.reset();
  return true;
}

ProfileTables::ProfileTables() = default;
ProfileTables::~ProfileTables() = default;
ProfileTables::ProfileTables(ProfileTables&&) noexcept = default;
ProfileTables& ProfileTables::operator=(ProfileTables&&) noexcept = default;
std::size_t ProfileTables::bytes() const { return data_ ? data_->tables.bytes() : 0; }
std::uint32_t Scheduler::wanted_tables(std::span<TablesWanted> out) { return impl_->wanted_tables(out); }
std::size_t Scheduler::drop_idle_tables(std::uint32_t frames) { return impl_->drop_idle_tables(frames); }
ObjectId Scheduler::add_object(int profile, const ObjectTransform& transform) {
  return impl_->add_object(profile, transform);
}
void Scheduler::remove_object(ObjectId id) { impl_->remove_object(id); }
void Scheduler::set_transform(ObjectId id, const ObjectTransform& transform) {
  impl_->set_transform(id, transform);
}
void Scheduler::set_velocity(ObjectId id, const float velocity[3]) { impl_->set_velocity(id, velocity); }
void Scheduler::set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level) {
  impl_->set_clamps(id, min_level, max_level);
}
void Scheduler::set_bias(ObjectId id, float quality_bias) { impl_->set_bias(id, quality_bias); }
void Scheduler::begin_frame(const Frame& frame) { impl_->begin_frame(frame); }
void Scheduler::update(std::uint32_t first, std::uint32_t count) { impl_->update(first, count); }
void Scheduler::end_frame() { impl_->end_frame(); }
std::uint32_t Scheduler::object_capacity() const { return impl_->config_.max_objects; }
bool Scheduler::alive(ObjectId id) const { return impl_->alive(id); }
std::uint8_t Scheduler::level(ObjectId id) const { return impl_->level_[id]; }
const std::uint8_t* Scheduler::level_array() const { return impl_->level_.data(); }
const std::uint8_t* Scheduler::flag_array() const { return impl_->flags_.data(); }
const std::uint8_t* Scheduler::previous_level_array() const { return impl_->from_level_.data(); }
const float* Scheduler::transition_array() const { return impl_->fade_.data(); }
const std::uint8_t* Scheduler::view_level_array(std::uint32_t view_class) const {
  return view_class < impl_->config_.max_view_classes
             ? &impl_->view_levels_[std::size_t(view_class) * impl_->config_.max_objects]
             : nullptr;
}
std::uint8_t Scheduler::flags(ObjectId id) const { return impl_->flags_[id]; }
std::uint8_t Scheduler::previous_level(ObjectId id) const { return impl_->from_level_[id]; }
float Scheduler::transition(ObjectId id) const { return impl_->fade_[id]; }
const float* Scheduler::scores(ObjectId id) const { return impl_->scores(id); }
const FrameStats& Scheduler::stats() const { return impl_->stats_; }
const SchedulerConfig& Scheduler::config() const { return impl_->config_; }
std::size_t Scheduler::table_bytes(int profile) const { return impl_->table_bytes(profile); }
std::size_t Scheduler::table_bytes(const Profile& profile, const SchedulerConfig& config, int view) {
  return Impl::table_bytes(profile, config, view);
}
float Scheduler::envelope_speed(float frequency_cpd) const { return impl_->envelope_speed(frequency_cpd); }
bool Scheduler::explain(ObjectId id, ObjectExplain* out) const { return impl_->explain(id, out); }
CutResult Scheduler::select_cut(const ClusterView& h, const ClusterLoss& loss,
                                const ObjectTransform& transform, const float velocity[3],
                                std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn) const {
  return impl_->select_cut(h, loss, transform, velocity, {}, scratch, drawn, nullptr);
}
CutResult Scheduler::select_cut(const ClusterView& h, const ClusterLoss& loss,
                                const ObjectTransform& transform, const float velocity[3],
                                std::span<CutGroupMemory> memory, std::span<std::uint8_t> scratch,
                                std::span<std::uint32_t> drawn) const {
  return impl_->select_cut(h, loss, transform, velocity, memory, scratch, drawn, nullptr);
}
CutResult Scheduler::select_cut(const ClusterView& h, const ClusterLoss& loss,
                                const ObjectTransform& transform, const float velocity[3],
                                std::span<CutGroupMemory> memory, const CutBudget& budget,
                                std::span<std::uint8_t> scratch, std::span<std::uint32_t> drawn) const {
  return impl_->select_cut(h, loss, transform, velocity, memory, scratch, drawn, nullptr, &budget);
}
CutStatus Scheduler::explain_cut(const ClusterView& h, const ClusterLoss& loss,
                                 const ObjectTransform& transform, const float velocity[3],
                                 std::span<std::uint8_t> scratch, std::span<GroupExplain> out) const {
  if (out.size() < h.groups.size()) return CutStatus::BadHierarchy;
  GroupExplain* explain = h.groups.empty() ? nullptr : out.data();
  return impl_->select_cut(h, loss, transform, velocity, {}, scratch, {}, explain).status;
}

}  // namespace acuity
