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
#include "acuity/scheduler.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

namespace acuity {
namespace {

constexpr float kDeg = 180.0f / std::numbers::pi_v<float>;
constexpr float kRad = std::numbers::pi_v<float> / 180.0f;
constexpr float kInf = std::numeric_limits<float>::infinity();

struct Vec3 { float x, y, z; };
[[gnu::always_inline]] inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
[[gnu::always_inline]] inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
[[gnu::always_inline]] inline Vec3 operator*(float s, Vec3 a) { return {s * a.x, s * a.y, s * a.z}; }
[[gnu::always_inline]] inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
[[gnu::always_inline]] inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
[[gnu::always_inline]] inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline bool finite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
inline Vec3 load(const float* p) { return {p[0], p[1], p[2]}; }

// Rotates v by the unit quaternion q = (x, y, z, w).
[[gnu::always_inline]] inline Vec3 rotate(const float* q, Vec3 v) {
  const Vec3 u{q[0], q[1], q[2]};
  const Vec3 t = 2.0f * cross(u, v);
  return v + q[3] * t + cross(u, t);
}
inline Vec3 rotate_inverse(const float* q, Vec3 v) {
  const float c[4] = {-q[0], -q[1], -q[2], q[3]};
  return rotate(c, v);
}
// atan2(y, x) in degrees for y >= 0, in [0, 180]: exact reductions to |t| <= tan 15 deg, then the
// odd Taylor series to t^9 (truncation below 6e-8 rad). Pure arithmetic: deterministic, ~4x libm's speed.
[[gnu::always_inline]] inline float atan2_deg(float y, float x) {
  constexpr float kTan15 = 0.26794919f, kSqrt3 = 1.7320508f;
  const float ax = std::abs(x);
  const bool swap = y > ax;  // atan(y/x) = 90 - atan(x/y)
  float t = swap ? ax / y : (ax > 0 ? y / ax : 0.0f);
  float base = 0;
  if (t > kTan15) {  // atan(t) = 30 deg + atan((sqrt3 t - 1) / (sqrt3 + t))
    t = (kSqrt3 * t - 1.0f) / (kSqrt3 + t);
    base = 30.0f;
  }
  const float t2 = t * t;
  const float a = base + kDeg * t * (1.0f + t2 * (-1.0f / 3 + t2 * (1.0f / 5 + t2 * (-1.0f / 7 + t2 * (1.0f / 9)))));
  const float first = swap ? 90.0f - a : a;
  return x < 0 ? 180.0f - first : first;
}
// Angle between unit vectors [deg], accurate at small angles.
[[gnu::always_inline]] inline float angle_deg(Vec3 a, Vec3 b) { return atan2_deg(length(cross(a, b)), dot(a, b)); }

// Per-orientation terms of the Default model's ln S at velocity v (already floored).
struct VelocityTerms {
  float a_term;      // A(v) = ln(prefactor v k(c2 v))
  float b;           // b(v) = 4 pi c1 (c2 v + 2) / 45.9  [per cpd]
  float peak;        // f_p = 2 / b  [cpd]
  float ln_s_peak;   // ln S at the peak
};

struct DalyConstants { float ln_prefactor, c1, c2, ln_2pi_c1, v_floor; };

// The fit's constants (from models.cpp, the one place they are written) in the fast path's form.
DalyConstants daly_constants(const ModelParams& p) {
  const DalyFitConstants f = daly_fit_constants(p.fit);
  return {float(std::log(f.prefactor)), float(f.c1), float(f.c2), float(std::log(2 * std::numbers::pi * f.c1)),
          float(std::max(p.drift, f.v_floor))};
}

VelocityTerms velocity_terms(float v, const DalyConstants& c) {
  const float x = c.c2 * v;
  const float l = std::abs(std::log10(x / 3.0f));
  VelocityTerms t;
  t.a_term = c.ln_prefactor + std::log(v) + std::log(6.1f + 7.3f * l * l * l);
  t.b = 4.0f * std::numbers::pi_v<float> * c.c1 * (x + 2.0f) / 45.9f;
  t.peak = 2.0f / t.b;
  t.ln_s_peak = t.a_term + 2.0f * (c.ln_2pi_c1 + std::log(t.peak)) - 2.0f;
  return t;
}

// For moving objects, "faster never finer" needs a threshold that never falls as speed rises. The
// low-pass CSF rises with speed below its argmax u*(f) (< 2 deg/s; Kelly's surface is nearly flat
// there), so each component is evaluated at max(v, u*(f)): the velocity envelope. u* is tabulated
// over ln f once, each entry the largest argmax on its interval plus a step, so the envelope is
// monotone by construction wherever S(f, .) is unimodal (a test checks it on a fine grid).
constexpr int kEnvelopeSize = 192;
constexpr float kEnvelopeLnF0 = -4.6f, kEnvelopeLnF1 = 5.3f;  // 0.01 .. 200 cpd

double argmax_speed(double f, const ModelParams& p) {
  auto ln_s = [&](double ln_u) { return -log_threshold(f, 0.0, std::exp(ln_u), ThresholdModel::Default, p); };
  double lo = std::log(std::max(p.drift, 1e-3)), hi = std::log(20.0);
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double a = hi - g * (hi - lo), b = lo + g * (hi - lo), sa = ln_s(a), sb = ln_s(b);
  for (int i = 0; i < 40; ++i) {  // golden section, one new evaluation a step; 0.618^40 ~ 4e-9
    if (sa < sb) { lo = a; a = b; sa = sb; b = lo + g * (hi - lo); sb = ln_s(b); }
    else         { hi = b; b = a; sb = sa; a = hi - g * (hi - lo); sa = ln_s(a); }
  }
  return std::exp(0.5 * (lo + hi));
}

// max over t < T, b < B of lost[t B + b] - ct[t stride + b], with stride B (one threshold row per
// orientation) or 0 (one row for all). Eight independent accumulators keep the adds in flight.
inline float max_excess(const float* lost, const float* ct, std::uint32_t T, std::uint32_t B, std::uint32_t stride) {
  float acc[8] = {-kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf, -kInf};
  for (std::uint32_t t = 0; t < T; ++t) {
    const float* l = lost + std::size_t(t) * B;
    const float* c = ct + std::size_t(t) * stride;
    std::uint32_t b = 0;
    for (; b + 8 <= B; b += 8)
      for (int j = 0; j < 8; ++j) acc[j] = std::max(acc[j], l[b + j] - c[b + j]);
    for (; b < B; ++b) acc[0] = std::max(acc[0], l[b] - c[b]);
  }
  float m = acc[0];
  for (int j = 1; j < 8; ++j) m = std::max(m, acc[j]);
  return m;
}

}  // namespace

struct Scheduler::ProfileCache {
  Profile profile{};
  std::vector<float> ln_lost;     // [(K-1) V T B], -inf where nothing is lost
  std::vector<float> ln_lost_any; // [(K-1) V B]: max over orientations (all a static object needs)
  std::vector<float> ln_band;     // [B] ln of the band centre [cpod]
  std::vector<float> cos_t, sin_t;  // [T] orientation unit vectors in the snapshot plane
  std::vector<float> view_right;  // [V][3] snapshot right = -direction x up, object space
};

// Everything that depends only on the configuration, computed once at creation.
struct Scheduler::Precomputed {
  DalyConstants daly{};
  VelocityTerms static_terms{};  // Default-model terms at the velocity floor
  float floor_velocity = 0;      // [deg/s]
  float ln_quality = 0, ln_margin = 0;
  float ecc_slope = 0;           // alpha / e2 [per cpd per deg]
  float distance_per_error = 0;  // Distance rule: distance_scale / tan(1 arcmin)
  // velocity_terms() tabulated over ln v, linear between nodes (error ~1e-5 in ln S).
  static constexpr int kTermsSize = 2048;
  static constexpr float kTermsLnV0 = -2.31f, kTermsLnV1 = 6.91f;  // 0.0993 .. 1000 deg/s
  VelocityTerms terms[kTermsSize] = {};
  VelocityTerms terms_at(float v) const {
    const float x = (std::log(v) - kTermsLnV0) * float(kTermsSize - 1) / (kTermsLnV1 - kTermsLnV0);
    if (!(x >= 0.0f && x < float(kTermsSize - 1))) return velocity_terms(v, daly);
    const int i = int(x);
    const float w = x - float(i);
    const VelocityTerms& p = terms[i];
    const VelocityTerms& q = terms[i + 1];
    VelocityTerms out;
    out.a_term = p.a_term + w * (q.a_term - p.a_term);
    out.b = p.b + w * (q.b - p.b);
    out.peak = 2.0f / out.b;
    out.ln_s_peak = p.ln_s_peak + w * (q.ln_s_peak - p.ln_s_peak);
    return out;
  }
  // The velocity envelope: u* bound for f in [f_j, f_j+1) [deg/s], and its largest value.
  float upper[kEnvelopeSize] = {};
  VelocityTerms upper_terms[kEnvelopeSize] = {};  // velocity_terms(upper[j])
  float largest = 0;
  int envelope_index(float ln_f) const {
    const float x = (ln_f - kEnvelopeLnF0) * float(kEnvelopeSize - 1) / (kEnvelopeLnF1 - kEnvelopeLnF0);
    if (!(x >= 0)) return 0;
    return x >= float(kEnvelopeSize - 1) ? kEnvelopeSize - 1 : int(x);
  }
  float speed_at(float ln_f) const { return upper[envelope_index(ln_f)]; }
};

struct Scheduler::EyeCache {
  double position[3];
  float rotation[4];
  Vec3 forward;          // world
  Vec3 velocity;         // world [m/s]
  Vec3 omega;            // head angular velocity, world [rad/s]
  bool valid;
  bool gaze;             // a usable gaze this frame
  Vec3 gaze_dir;         // world, unit
  bool gaze_moving;      // measured gaze velocity
  Vec3 gaze_velocity;    // world tangent velocity of the gaze direction [deg/s]
  float focal_px;        // horizontal focal length [px]
  float center_right, center_up;  // tangent offsets of the projection centre (off-axis frusta)
};

Scheduler::Scheduler(const SchedulerConfig& config) : config_(config) {
  if (config_.triangle_budget > 0) config_.keep_scores = true;  // the budget pass needs them
  const std::size_t n = config_.max_objects;
  profiles_.resize(config_.max_profiles);
  profile_of_.assign(n, -1);
  position_.assign(3 * n, 0.0);
  previous_position_.assign(3 * n, 0.0);
  rotation_.assign(4 * n, 0.0f);
  velocity_.assign(3 * n, 0.0f);
  scale_.assign(n, 1.0f);
  bias_.assign(n, 1.0f);
  explicit_velocity_.assign(n, 0);
  fresh_.assign(n, 0);
  min_level_.assign(n, 0);
  max_level_.assign(n, 255);
  chosen_.assign(n, 0);
  next_.assign(n, 0);
  level_.assign(n, 0);
  from_level_.assign(n, 0);
  flags_.assign(n, 0);
  calm_frames_.assign(n, 0);
  wait_frames_.assign(n, 0);
  fade_.assign(n, 1.0f);
  if (config_.keep_scores) scores_.assign(n * kMaxLevels, 0.0f);
  free_list_.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) free_list_.push_back(static_cast<std::uint32_t>(n - 1 - i));
  heap_.reserve(n);
  eyes_.resize(2);
  pre_ = std::make_unique<Precomputed>();
  Precomputed& pre = *pre_;
  pre.daly = daly_constants(config_.params);
  const bool daly_model = config_.model == ThresholdModel::Default || config_.model == ThresholdModel::KellyDaly;
  pre.floor_velocity = daly_model ? pre.daly.v_floor : static_cast<float>(config_.params.drift);
  pre.static_terms = velocity_terms(std::max(pre.floor_velocity, 1e-3f), pre.daly);
  pre.ln_quality = std::log(config_.quality);
  pre.ln_margin = std::log(std::max(1e-6f, 1.0f - config_.hysteresis_margin));
  pre.ecc_slope = static_cast<float>(config_.params.alpha / config_.params.e2);
  pre.distance_per_error = config_.distance_scale / std::tan(kRad / 60.0f);
  for (int i = 0; i < Precomputed::kTermsSize; ++i)
    pre.terms[i] = velocity_terms(std::exp(Precomputed::kTermsLnV0 + (Precomputed::kTermsLnV1 - Precomputed::kTermsLnV0) *
                                                                      float(i) / float(Precomputed::kTermsSize - 1)), pre.daly);
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
}

float Scheduler::envelope_speed(float frequency_cpd) const { return pre_->speed_at(std::log(frequency_cpd)); }

Scheduler::~Scheduler() = default;

int Scheduler::add_profile(const Profile& p) {
  if (profile_count_ >= config_.max_profiles) return -1;
  ProfileCache& c = profiles_[profile_count_];
  c.profile = p;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  c.ln_lost.resize(std::size_t(K - 1) * V * T * B);
  for (std::size_t i = 0; i < c.ln_lost.size(); ++i) c.ln_lost[i] = p.lost[i] > 0 ? std::log(p.lost[i]) : -kInf;
  c.ln_lost_any.assign(std::size_t(K - 1) * V * B, -kInf);
  for (std::size_t kv = 0; kv < std::size_t(K - 1) * V; ++kv)
    for (std::uint32_t t = 0; t < T; ++t)
      for (std::uint32_t b = 0; b < B; ++b)
        c.ln_lost_any[kv * B + b] = std::max(c.ln_lost_any[kv * B + b], c.ln_lost[(kv * T + t) * B + b]);
  c.ln_band.resize(B);
  for (std::uint32_t b = 0; b < B; ++b) c.ln_band[b] = std::log(p.bands[b]);
  c.cos_t.resize(T);
  c.sin_t.resize(T);
  for (std::uint32_t t = 0; t < T; ++t) {
    c.cos_t[t] = std::cos(p.orientations[t] * kRad);
    c.sin_t[t] = std::sin(p.orientations[t] * kRad);
  }
  c.view_right.resize(3 * std::size_t(V));
  for (std::uint32_t v = 0; v < V; ++v) {
    const Vec3 r = cross(-1.0f * load(p.views[v].direction), load(p.views[v].up));
    c.view_right[3 * v] = r.x; c.view_right[3 * v + 1] = r.y; c.view_right[3 * v + 2] = r.z;
  }
  return static_cast<int>(profile_count_++);
}

ObjectId Scheduler::add_object(int profile, const ObjectTransform& t) {
  if (profile < 0 || profile >= static_cast<int>(profile_count_) || free_list_.empty()) return kInvalidObject;
  const ObjectId id = free_list_.back();
  free_list_.pop_back();
  profile_of_[id] = profile;
  set_transform(id, t);
  for (int k = 0; k < 3; ++k) { previous_position_[3 * id + k] = t.position[k]; velocity_[3 * id + k] = 0; }
  explicit_velocity_[id] = 0;
  fresh_[id] = 1;
  min_level_[id] = 0;
  max_level_[id] = 255;
  bias_[id] = 1.0f;
  level_[id] = from_level_[id] = chosen_[id] = next_[id] = std::min<std::uint8_t>(config_.fallback_level,
      static_cast<std::uint8_t>(profiles_[profile].profile.meta.level_count - 1));
  flags_[id] = 0;
  calm_frames_[id] = wait_frames_[id] = 0;
  fade_[id] = 1.0f;
  return id;
}

void Scheduler::remove_object(ObjectId id) {
  if (!alive(id)) return;
  profile_of_[id] = -1;
  free_list_.push_back(id);
}

void Scheduler::set_transform(ObjectId id, const ObjectTransform& t) {
  if (!alive(id)) return;
  for (int k = 0; k < 3; ++k) position_[3 * id + k] = t.position[k];
  for (int k = 0; k < 4; ++k) rotation_[4 * id + k] = t.rotation[k];
  scale_[id] = t.scale;
}

void Scheduler::set_velocity(ObjectId id, const float v[3]) {
  if (!alive(id)) return;
  for (int k = 0; k < 3; ++k) velocity_[3 * id + k] = v[k];
  explicit_velocity_[id] = 1;
}

void Scheduler::set_clamps(ObjectId id, std::uint8_t min_level, std::uint8_t max_level) {
  if (!alive(id)) return;
  min_level_[id] = min_level;
  max_level_[id] = std::max(min_level, max_level);
}

void Scheduler::set_bias(ObjectId id, float quality_bias) {
  if (alive(id)) bias_[id] = quality_bias;
}

const float* Scheduler::scores(ObjectId id) const {
  return config_.keep_scores && alive(id) ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
}

void Scheduler::begin_frame(const Frame& frame) {
  eye_count_ = std::clamp<std::uint32_t>(frame.eye_count, 1, 2);
  dt_ = std::isfinite(frame.dt) && frame.dt > 0 ? frame.dt : 0.0f;
  saccade_ = false;
  stats_ = FrameStats{};
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    const Eye& e = frame.eyes[i];
    const Gaze& g = frame.gaze[i];
    EyeCache& c = eyes_[i];
    for (int k = 0; k < 3; ++k) c.position[k] = e.position[k];
    for (int k = 0; k < 4; ++k) c.rotation[k] = e.orientation[k];
    const float qn = std::sqrt(e.orientation[0] * e.orientation[0] + e.orientation[1] * e.orientation[1] +
                               e.orientation[2] * e.orientation[2] + e.orientation[3] * e.orientation[3]);
    const float tan_l = std::tan(e.fov_deg[0] * kRad), tan_r = std::tan(e.fov_deg[1] * kRad);
    const float tan_u = std::tan(e.fov_deg[2] * kRad), tan_d = std::tan(e.fov_deg[3] * kRad);
    c.valid = std::isfinite(e.position[0]) && std::isfinite(e.position[1]) && std::isfinite(e.position[2]) &&
              std::abs(qn - 1.0f) < 1e-3f && finite(load(e.velocity)) && finite(load(e.angular_velocity)) &&
              tan_r > tan_l && tan_u > tan_d && e.viewport[0] > 0 && e.viewport[1] > 0 &&
              std::isfinite(tan_r - tan_l) && std::isfinite(tan_u - tan_d);
    if (c.valid) for (float& q : c.rotation) q /= qn;
    c.forward = rotate(c.rotation, {0, 0, -1});
    c.velocity = load(e.velocity);
    c.omega = kRad * load(e.angular_velocity);
    c.focal_px = static_cast<float>(e.viewport[0]) / (tan_r - tan_l);
    c.center_right = 0.5f * (tan_l + tan_r);
    c.center_up = 0.5f * (tan_u + tan_d);
    const Vec3 gd = load(g.direction);
    const float gl = length(gd);
    c.gaze = g.valid && g.confidence >= config_.min_gaze_confidence && std::isfinite(gl) && gl > 0.5f;
    c.gaze_dir = c.gaze ? rotate(c.rotation, (1.0f / gl) * gd) : c.forward;
    const Vec3 gw = load(g.angular_velocity);
    c.gaze_moving = c.gaze && g.has_velocity && finite(gw);
    if (c.gaze_moving && config_.saccade_speed > 0 && length(gw) > config_.saccade_speed) {
      // A saccade: the time to switch, but its own sweep of the retina lasts a few frames while the
      // level chosen now is seen in the fixation after it. So the eye counts as fixating (Daly's
      // pursuit model), not as moving at saccade speed.
      saccade_ = true;
      c.gaze_moving = false;
    }
    if (c.gaze_moving) {
      // d(gaze)/dt in the world: eye-in-head rotation carried by the head, plus the head's own.
      const Vec3 in_head = rotate(c.rotation, cross(gw, (1.0f / gl) * gd));
      c.gaze_velocity = in_head + kDeg * cross(c.omega, c.gaze_dir);
    }
    stats_.gaze_used |= c.gaze;
  }
}

void Scheduler::update(std::uint32_t first, std::uint32_t count) {
  const std::uint32_t end = std::min(config_.max_objects, first + std::min(count, config_.max_objects));
  for (std::uint32_t id = first; id < end; ++id)
    if (profile_of_[id] >= 0) select(id);
}

// One eye's view of one object. scores_out (K floats) and ex are optional.
Scheduler::Choice Scheduler::evaluate(ObjectId id, const EyeCache& eye, float* scores_out,
                                      ObjectExplain* ex) const {
  const ProfileCache& pc = profiles_[profile_of_[id]];
  const Profile& p = pc.profile;
  const std::uint32_t K = p.meta.level_count, V = p.meta.view_count, T = p.meta.orientation_count,
                      B = p.meta.band_count;
  const std::uint8_t fallback = static_cast<std::uint8_t>(std::min<std::uint32_t>(config_.fallback_level, K - 1));
  const Choice invalid{fallback, fallback, kFlagInvalidInput};
  if (scores_out) std::fill(scores_out, scores_out + K, 0.0f);
  if (!eye.valid) return invalid;

  // Camera-relative geometry: the double subtraction first, so 1e7 m from the origin is exact.
  const float* q = &rotation_[4 * std::size_t(id)];
  const float s = scale_[id];
  const Vec3 centre = rotate(q, s * load(p.meta.sphere));
  const Vec3 rel{static_cast<float>(position_[3 * id] - eye.position[0]) + centre.x,
                 static_cast<float>(position_[3 * id + 1] - eye.position[1]) + centre.y,
                 static_cast<float>(position_[3 * id + 2] - eye.position[2]) + centre.z};
  const Vec3 vel = load(&velocity_[3 * std::size_t(id)]);
  const float r = s * p.meta.sphere[3];
  const float qn = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  const float bias = config_.quality * bias_[id];
  if (!finite(rel) || !finite(vel) || !(r > 0) || !std::isfinite(r) || !(std::abs(qn - 1.0f) < 1e-3f) ||
      !(bias > 0) || !std::isfinite(bias))
    return invalid;
  const float d = length(rel);
  if (!(d > r)) return {0, 0, kFlagEyeInside};
  const Vec3 u = (1.0f / d) * rel;
  const float sin_radius = r / d;
  const float radius_deg = atan2_deg(sin_radius, std::sqrt(1.0f - sin_radius * sin_radius));  // asin
  const float diameter_deg = 2.0f * radius_deg;

  if (config_.rule == SelectionRule::Distance || config_.rule == SelectionRule::ScreenSize) {
    std::uint8_t level = 0;
    for (std::uint32_t k = 1; k < K; ++k) {
      const float error = p.levels[k].geometric_error * 2.0f * r;  // world units
      const bool ok = config_.rule == SelectionRule::Distance
                          ? d >= pre_->distance_per_error * error
                          : error / d * eye.focal_px <= config_.pixel_error;
      if (ok) level = static_cast<std::uint8_t>(k);
    }
    return {level, level, 0};
  }

  Choice out{0, 0, eye.gaze ? std::uint8_t(0) : std::uint8_t(kFlagNoGaze)};

  // Image-plane angular velocity [deg/s] (world tangent vector), then retinal slip.
  const Vec3 v_rel = vel - eye.velocity;
  const Vec3 image = kDeg * ((1.0f / d) * (v_rel - dot(v_rel, u) * u) - cross(eye.omega, u));
  Vec3 slip{0, 0, 0};
  if (eye.gaze_moving) {
    slip = image - eye.gaze_velocity;
  } else {
    const float vi = length(image);
    if (vi > 0) slip = (daly_retinal_velocity(vi, config_.params) / vi) * image;
  }

  // Display limit: radial pixels per degree at the object's direction, halved.
  const float cos_phi = std::clamp(dot(u, eye.forward), 0.05f, 1.0f);
  const float nyquist_cpd = 0.5f * eye.focal_px * kRad / (cos_phi * cos_phi);
  const Precomputed& pre = *pre_;
  const float inv_diam = 1.0f / diameter_deg, ln_diam = std::log(diameter_deg);
  const float ln_q = pre.ln_quality + (bias_[id] != 1.0f ? std::log(bias_[id]) : 0.0f);
  const float ln_q_coarse = ln_q + pre.ln_margin;
  const bool all_levels = scores_out || ex;
  // ln CT of the Default model at band b for velocity terms vt and eccentricity slope a [per cpd].
  auto default_ln_ct = [&](const VelocityTerms& vt, std::uint32_t b, float a) {
    const float f = p.bands[b] * inv_diam;
    const float ln_f = pc.ln_band[b] - ln_diam;
    const float above = -vt.a_term - 2.0f * (pre.daly.ln_2pi_c1 + ln_f) + (vt.b + a) * f;
    const float below = -vt.ln_s_peak + a * f;
    return f > nyquist_cpd ? kInf : (f >= vt.peak ? above : below);
  };

  float e;
  if (eye.gaze) e = std::max(0.0f, angle_deg(u, eye.gaze_dir) - radius_deg - config_.gaze_uncertainty_deg);
  else e = std::max(0.0f, angle_deg(u, eye.forward) - radius_deg - config_.no_gaze_radius_deg);

  // The profile's view nearest to the direction from the object to the eye.
  const Vec3 to_eye = rotate_inverse(q, -1.0f * u);
  const float dir[3] = {to_eye.x, to_eye.y, to_eye.z};
  const std::uint16_t* cand = p.lookup + cube_cell(dir, p.meta.lookup_resolution) * kLookupCandidates;
  std::uint32_t view = cand[0];
  float best = -2.0f;
  for (std::uint32_t j = 0; j < kLookupCandidates; ++j) {
    const float dd = dot(to_eye, load(p.views[cand[j]].direction));
    if (dd > best) { best = dd; view = cand[j]; }
  }
  // Slip in the snapshot's image axes, so it meets the profile's orientations in one frame.
  float vx = 0, vy = 0;
  if (slip.x != 0.0f || slip.y != 0.0f || slip.z != 0.0f) {
    vx = dot(slip, rotate(q, load(&pc.view_right[3 * std::size_t(view)])));
    vy = dot(slip, rotate(q, load(p.views[view].up)));
  }
  const bool moving = vx != 0.0f || vy != 0.0f;

  const float a = pre.ecc_slope * e;  // ln CT grows by a per cpd with eccentricity

  // ln CT per (orientation, band). A static object's velocity is the drift floor in every
  // orientation, so one row serves all of them (rows = 1).
  float ln_ct[kMaxOrientations * kMaxBands];
  float v_t[kMaxOrientations];
  const std::uint32_t rows = moving || config_.model != ThresholdModel::Default ? T : 1;
  for (std::uint32_t t = 0; t < rows; ++t) {
    v_t[t] = moving ? std::max(std::abs(vx * pc.cos_t[t] + vy * pc.sin_t[t]), pre.floor_velocity) : pre.floor_velocity;
    float* row = ln_ct + t * B;
    if (config_.rule == SelectionRule::Reddy) {  // the visible limit per orientation, in cpod
      row[0] = std::min(reddy_cutoff(v_t[t], e), nyquist_cpd) * diameter_deg;
      continue;
    }
    if (config_.model == ThresholdModel::Default) {
      const VelocityTerms own = moving ? pre.terms_at(v_t[t]) : pre.static_terms;
      const bool enveloped = moving && v_t[t] < pre_->largest;
      for (std::uint32_t b = 0; b < B; ++b) {
        const int j = enveloped ? pre.envelope_index(pc.ln_band[b] - ln_diam) : 0;
        row[b] = default_ln_ct(enveloped && pre.upper[j] > v_t[t] ? pre.upper_terms[j] : own, b, a);
      }
    } else {
      for (std::uint32_t b = 0; b < B; ++b) {
        const float f = p.bands[b] * inv_diam;
        row[b] = f > nyquist_cpd ? kInf : log_threshold(f, e, v_t[t], config_.model, config_.params);
      }
    }
  }
  const std::uint32_t stride = rows == 1 ? 0 : B;  // a static object's one row serves every orientation

  // ln(score_k q) = max over (t, b) of ln lost - ln CT. Levels are scanned from the coarsest; without
  // scores or explain, the scan stops at the first level that passes even the hysteresis margin.
  const std::size_t TB = std::size_t(T) * B;
  // Reddy: a finer level's smallest feature F is visible when it lies at or below the limit, so
  // level k's score is the largest limit / F over the levels j < k and every orientation.
  float reddy_prefix[kMaxLevels] = {};
  if (config_.rule == SelectionRule::Reddy)
    for (std::uint32_t j = 0; j + 1 < K; ++j) {
      float worst = reddy_prefix[j];
      for (std::uint32_t t = 0; t < T; ++t) {
        const float F = p.feature_frequency(j, view, t);
        if (F > 0) worst = std::max(worst, ln_ct[t * stride] / F);
      }
      reddy_prefix[j + 1] = worst;
    }
  bool fine_found = false;
  for (std::uint32_t k = K - 1; k >= 1; --k) {
    float m = -kInf;
    if (config_.rule == SelectionRule::Reddy) {
      m = reddy_prefix[k] > 0 ? std::log(reddy_prefix[k]) : -kInf;
    } else {
      // A static object's thresholds do not depend on orientation: its per-band maxima suffice.
      const std::vector<float>& lost = stride ? pc.ln_lost : pc.ln_lost_any;
      const std::uint32_t t_count = stride ? T : 1;
      const std::size_t per_view = std::size_t(t_count) * B;
      const std::uint32_t blended = config_.view_blend == ViewBlend::Max3 ? kLookupCandidates : 1;
      for (std::uint32_t j = 0; j < blended; ++j) {
        const std::uint32_t w = blended == 1 ? view : cand[j];
        m = std::max(m, max_excess(&lost[((k - 1) * std::size_t(V) + w) * per_view], ln_ct, t_count, B, stride));
      }
    }
    if (!fine_found && m <= ln_q) { out.fine = static_cast<std::uint8_t>(k); fine_found = true; }
    if (out.coarse == 0 && m <= ln_q_coarse) out.coarse = static_cast<std::uint8_t>(k);
    if (scores_out) scores_out[k] = std::exp(m - ln_q);
    if (ex) {
      LevelExplain& le = ex->levels[k];
      le.score = std::exp(m - ln_q);
      std::uint32_t arg = 0;  // the limiting component, found again (explain is not the hot path)
      if (config_.rule == SelectionRule::Reddy) {
        float best_ratio = -kInf;
        for (std::uint32_t j = 0; j < k; ++j)
          for (std::uint32_t t = 0; t < T; ++t) {
            const float F = p.feature_frequency(j, view, t);
            if (F > 0 && ln_ct[t * stride] / F > best_ratio) { best_ratio = ln_ct[t * stride] / F; arg = t * B; }
          }
      } else {
        const float* lost = &pc.ln_lost[((k - 1) * std::size_t(V) + view) * TB];
        float best_x = -kInf;
        for (std::uint32_t i = 0; i < T * B; ++i) {
          const float x = lost[i] - ln_ct[(i / B) * stride + i % B];
          if (x > best_x) { best_x = x; arg = i; }
        }
      }
      le.orientation = static_cast<std::uint8_t>(arg / B);
      le.band = static_cast<std::uint8_t>(arg % B);
      le.frequency_cpd = p.bands[le.band] * inv_diam;
      le.threshold = config_.rule == SelectionRule::Reddy ? 0.0f : std::exp(std::min(ln_ct[(arg / B) * stride + arg % B], 80.0f));
    }
    if (out.coarse != 0 && !all_levels) break;
  }
  if (ex) {
    ex->distance_m = d;
    ex->angular_diameter_deg = diameter_deg;
    ex->eccentricity_deg = e;
    ex->image_velocity_deg_s = length(image);
    ex->retinal_velocity_deg_s = length(slip);
    ex->view = view;
    ex->level_count = static_cast<std::uint8_t>(K);
    ex->levels[0] = LevelExplain{0, 0, 0, 0, 0};
  }
  return out;
}

void Scheduler::select(ObjectId id) {
  const Profile& p = profiles_[profile_of_[id]].profile;
  const std::uint32_t K = p.meta.level_count;
  double* pos = &position_[3 * std::size_t(id)];
  double* prev = &previous_position_[3 * std::size_t(id)];
  if (!explicit_velocity_[id])
    for (int k = 0; k < 3; ++k)
      velocity_[3 * id + k] = dt_ > 0 ? static_cast<float>((pos[k] - prev[k]) / dt_) : 0.0f;
  for (int k = 0; k < 3; ++k) prev[k] = pos[k];

  std::uint8_t fine = 255, coarse = 255, flags = 0;
  float* kept = config_.keep_scores ? &scores_[std::size_t(id) * kMaxLevels] : nullptr;
  float eye_scores[kMaxLevels];
  for (std::uint32_t i = 0; i < eye_count_; ++i) {  // both eyes agree: the finer need wins
    const Choice c = evaluate(id, eyes_[i], kept ? eye_scores : nullptr, nullptr);
    fine = std::min(fine, c.fine);
    coarse = std::min(coarse, c.coarse);
    flags |= c.flags;
    if (kept)
      for (std::uint32_t k = 0; k < K; ++k) kept[k] = i == 0 ? eye_scores[k] : std::max(kept[k], eye_scores[k]);
  }
  const std::uint8_t hi = static_cast<std::uint8_t>(std::min<std::uint32_t>(max_level_[id], K - 1));
  const std::uint8_t lo = std::min(min_level_[id], hi);
  fine = std::clamp(fine, lo, hi);
  coarse = std::clamp(coarse, lo, hi);

  const std::uint8_t current = chosen_[id];
  std::uint8_t next = current;
  if (fresh_[id]) {  // a new object takes its first level at once
    next = fine;
    fresh_[id] = 0;
  } else if ((flags & kFlagInvalidInput) || fine < current) {  // refine (or fall back) at once
    next = fine;
    calm_frames_[id] = wait_frames_[id] = 0;
  } else if (coarse > current) {
    ++calm_frames_[id];
    const bool settled = calm_frames_[id] >= config_.hysteresis_frames;
    const bool gate = config_.saccade_speed <= 0 || saccade_ || wait_frames_[id] >= config_.max_coarsen_wait;
    if (settled && gate) {
      next = coarse;
      calm_frames_[id] = wait_frames_[id] = 0;
    } else {
      flags |= kFlagHeld;
      if (settled) ++wait_frames_[id];
    }
  } else {
    calm_frames_[id] = wait_frames_[id] = 0;
  }
  chosen_[id] = next_[id] = next;
  flags_[id] = flags;
}

void Scheduler::end_frame() {
  if (config_.triangle_budget > 0) apply_budget();
  FrameStats& st = stats_;
  st.triangles = 0;
  st.changed = st.invalid = st.budget_forced = 0;
  for (std::uint32_t id = 0; id < config_.max_objects; ++id) {
    if (profile_of_[id] < 0) continue;
    if (next_[id] != level_[id]) {  // a change event; the cross-fade starts from the drawn level
      from_level_[id] = level_[id];
      fade_[id] = config_.transition_seconds > 0 ? 0.0f : 1.0f;
      flags_[id] |= kFlagChanged;
      level_[id] = next_[id];
    } else if (fade_[id] < 1.0f) {
      fade_[id] = config_.transition_seconds > 0 ? std::min(1.0f, fade_[id] + dt_ / config_.transition_seconds) : 1.0f;
    }
    st.triangles += profiles_[profile_of_[id]].profile.levels[level_[id]].triangles;
    st.changed += (flags_[id] & kFlagChanged) != 0;
    st.invalid += (flags_[id] & kFlagInvalidInput) != 0;
    st.budget_forced += (flags_[id] & kFlagBudgetForced) != 0;
  }
}

// Funkhouser & Sequin: while over budget, coarsen by one level the object whose next level costs
// the least perceptual harm (its score) per triangle saved. Ties go to the lower id.
void Scheduler::apply_budget() {
  std::uint64_t total = 0;
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0) total += profiles_[profile_of_[id]].profile.levels[next_[id]].triangles;
  if (total <= config_.triangle_budget) return;

  auto can_coarsen = [&](std::uint32_t id) {
    const std::uint32_t K = profiles_[profile_of_[id]].profile.meta.level_count;
    return next_[id] + 1u < std::min<std::uint32_t>(max_level_[id] + 1u, K) && !(flags_[id] & kFlagEyeInside);
  };
  auto harm = [&](std::uint32_t id) {
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint32_t l = next_[id];
    const float saved = static_cast<float>(p.levels[l].triangles) - static_cast<float>(p.levels[l + 1].triangles);
    return scores_[std::size_t(id) * kMaxLevels + l + 1] / std::max(saved, 1.0f);
  };
  // Min-heap on (harm, id).
  auto later = [&](std::uint32_t x, std::uint32_t y) {
    const float hx = harm(x), hy = harm(y);
    return hx != hy ? hx > hy : x > y;
  };
  heap_.clear();
  for (std::uint32_t id = 0; id < config_.max_objects; ++id)
    if (profile_of_[id] >= 0 && can_coarsen(id)) heap_.push_back(id);
  std::make_heap(heap_.begin(), heap_.end(), later);
  while (total > config_.triangle_budget && !heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), later);
    const std::uint32_t id = heap_.back();
    heap_.pop_back();
    const Profile& p = profiles_[profile_of_[id]].profile;
    const std::uint8_t l = next_[id];
    total -= p.levels[l].triangles - p.levels[l + 1].triangles;
    if (scores_[std::size_t(id) * kMaxLevels + l + 1] > 1.0f) flags_[id] |= kFlagBudgetForced;
    next_[id] = static_cast<std::uint8_t>(l + 1);
    if (can_coarsen(id)) {
      heap_.push_back(id);
      std::push_heap(heap_.begin(), heap_.end(), later);
    }
  }
}

bool Scheduler::explain(ObjectId id, ObjectExplain* out) const {
  if (!alive(id) || !out) return false;
  *out = ObjectExplain{};
  // The eye that needs the finer level is the one that decides.
  std::uint8_t best = 255;
  for (std::uint32_t i = 0; i < eye_count_; ++i) {
    ObjectExplain tmp{};
    const Choice c = evaluate(id, eyes_[i], nullptr, &tmp);
    if (c.fine < best) { best = c.fine; *out = tmp; }
  }
  out->level = level_[id];
  out->level_count = static_cast<std::uint8_t>(profiles_[profile_of_[id]].profile.meta.level_count);
  return true;
}

}  // namespace acuity
