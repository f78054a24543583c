// acuity.Profile, acuity.Scheduler and the frame structs, with numpy batch arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "acuity/file.hpp"
#include "acuity/profile.hpp"
#include "acuity/scheduler.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

std::shared_ptr<OwnedProfile> open_owned(Blob blob, const std::string& where) {
  auto p = std::make_shared<OwnedProfile>();
  p->blob = std::move(blob);
  ProfileError error;
  if (open_profile(p->blob.data(), p->blob.size, &p->view, &error) != ProfileStatus::Ok)
    throw py::value_error(where + ": " + to_string(error.status) + ": " + error.message);
  return p;
}

std::shared_ptr<OwnedProfile> profile_from_bytes(const py::bytes& bytes) {
  const std::string s = bytes;
  if (s.size() < 32)
    throw py::value_error("profile bytes: " + std::to_string(s.size()) +
                          " bytes, too small for a profile's 32-byte header");
  Blob blob;
  blob.size = s.size();
  blob.storage.assign((s.size() + 7) / 8, 0);
  std::memcpy(blob.storage.data(), s.data(), s.size());
  return open_owned(std::move(blob), "profile bytes");
}

template <std::size_t N, class T>
void set_array(T (&dst)[N], const std::array<T, N>& src) {
  for (std::size_t i = 0; i < N; ++i) dst[i] = src[i];
}
template <std::size_t N, class T>
std::array<T, N> get_array(const T (&src)[N]) {
  std::array<T, N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = src[i];
  return out;
}

#define ACUITY_ARRAY_PROPERTY(Class, field, T, N, doc)                 \
  def_property(                                                        \
      #field, [](const Class& c) { return get_array<N, T>(c.field); }, \
      [](Class& c, const std::array<T, N>& v) { set_array<N, T>(c.field, v); }, doc)

using F64 = py::array_t<double, py::array::c_style | py::array::forcecast>;
using F32 = py::array_t<float, py::array::c_style | py::array::forcecast>;
using U32 = py::array_t<std::uint32_t, py::array::c_style | py::array::forcecast>;

void require_rows(const py::array& a, py::ssize_t n, py::ssize_t cols, const char* name) {
  const bool ok = cols == 0 ? (a.ndim() == 1 && a.shape(0) == n)
                            : (a.ndim() == 2 && a.shape(0) == n && a.shape(1) == cols);
  if (!ok)
    throw py::value_error(std::string(name) + ": expected shape (" + std::to_string(n) +
                          (cols ? ", " + std::to_string(cols) : std::string()) + ")");
}

// Row i of shape-checked (N, 3) positions, (N, 4) rotations and (N,) scales.
ObjectTransform transform_at(const F64& position, const F32& rotation, const F32& scale, py::ssize_t i) {
  ObjectTransform t;
  for (int k = 0; k < 3; ++k) t.position[k] = position.at(i, k);
  for (int k = 0; k < 4; ++k) t.rotation[k] = rotation.at(i, k);
  t.scale = scale.at(i);
  return t;
}

// Holds the profiles it was given so their bytes outlive the scheduler.
struct PyScheduler {
  Scheduler scheduler;
  std::vector<std::shared_ptr<OwnedProfile>> profiles;
  std::uint32_t live = 0;  // objects added and not removed
  bool in_frame = false;
  explicit PyScheduler(const SchedulerConfig& c) : scheduler(c) {}

  // Raises IndexError naming the first id that is not a live object; called before any change.
  void require_alive(const U32& ids, const char* function) const {
    if (ids.ndim() != 1) throw py::value_error(std::string(function) + ": ids must be one-dimensional");
    auto id = ids.unchecked<1>();
    for (py::ssize_t i = 0; i < ids.shape(0); ++i)
      if (!scheduler.alive(id(i)))
        throw py::index_error(std::string(function) + ": object " + std::to_string(id(i)) +
                              " does not exist (never added, or removed); nothing was changed");
  }
  // The frame with `views` (checked as the C ABI checks them: count and classes).
  Frame with_views(const Frame& f, const std::vector<View>& views, const char* function) const {
    const SchedulerConfig& c = scheduler.config();
    if (views.size() > c.max_views)
      throw py::value_error(std::string(function) + ": " + std::to_string(views.size()) +
                            " views, more than max_views " + std::to_string(c.max_views));
    for (std::size_t i = 0; i < views.size(); ++i)
      if (views[i].view_class >= c.max_view_classes)
        throw py::value_error(std::string(function) + ": views[" + std::to_string(i) +
                              "].view_class is not below max_view_classes " +
                              std::to_string(c.max_view_classes));
    Frame out = f;
    out.views = views.data();
    out.view_count = static_cast<std::uint32_t>(views.size());
    return out;
  }
  void require_alive(std::uint32_t id, const char* function) const {
    if (!scheduler.alive(id))
      throw py::index_error(std::string(function) + ": object " + std::to_string(id) +
                            " does not exist (never added, or removed)");
  }

  py::array_t<std::uint32_t> add_objects(U32 profile, F64 position, F32 rotation, F32 scale) {
    const py::ssize_t n = profile.shape(0);
    require_rows(profile, n, 0, "profile");
    require_rows(position, n, 3, "position");
    require_rows(rotation, n, 4, "rotation");
    require_rows(scale, n, 0, "scale");
    py::array_t<std::uint32_t> ids(n);
    auto out = ids.mutable_unchecked<1>();
    auto pr = profile.unchecked<1>();
    // All or nothing: every profile index and the capacity are checked before anything is added.
    for (py::ssize_t i = 0; i < n; ++i)
      if (pr(i) >= profiles.size())
        throw py::index_error("add_objects: row " + std::to_string(i) + ": profile " + std::to_string(pr(i)) +
                              " was not added (" + std::to_string(profiles.size()) +
                              " profiles); nothing was added");
    if (std::uint64_t(n) > scheduler.object_capacity() - live)
      throw py::value_error("add_objects: " + std::to_string(n) + " objects do not fit (" +
                            std::to_string(live) + " of " + std::to_string(scheduler.object_capacity()) +
                            " used); nothing was added");
    for (py::ssize_t i = 0; i < n; ++i) {
      out(i) = scheduler.add_object(static_cast<int>(pr(i)), transform_at(position, rotation, scale, i));
      if (out(i) == kInvalidObject) {  // cannot happen after the checks above; undo to keep the contract
        for (py::ssize_t j = 0; j < i; ++j) scheduler.remove_object(out(j));
        live -= std::uint32_t(i);
        throw std::runtime_error("add_objects: the scheduler refused row " + std::to_string(i) +
                                 "; nothing was added");
      }
      ++live;
    }
    return ids;
  }

  void set_transforms(U32 ids, F64 position, F32 rotation, F32 scale) {
    const py::ssize_t n = ids.shape(0);
    require_rows(position, n, 3, "position");
    require_rows(rotation, n, 4, "rotation");
    require_rows(scale, n, 0, "scale");
    require_alive(ids, "set_transforms");
    auto id = ids.unchecked<1>();
    for (py::ssize_t i = 0; i < n; ++i)
      scheduler.set_transform(id(i), transform_at(position, rotation, scale, i));
  }

  void set_velocities(U32 ids, F32 velocity) {
    require_rows(velocity, ids.shape(0), 3, "velocity");
    require_alive(ids, "set_velocities");
    auto id = ids.unchecked<1>();
    auto v = velocity.unchecked<2>();
    for (py::ssize_t i = 0; i < ids.shape(0); ++i) {
      const float w[3] = {v(i, 0), v(i, 1), v(i, 2)};
      scheduler.set_velocity(id(i), w);
    }
  }

  template <class Get>
  py::array_t<std::uint8_t> per_object(U32 ids, Get get) const {
    py::array_t<std::uint8_t> out(ids.shape(0));
    auto o = out.mutable_unchecked<1>();
    auto id = ids.unchecked<1>();
    for (py::ssize_t i = 0; i < ids.shape(0); ++i) {
      if (!scheduler.alive(id(i)))
        throw py::index_error("object " + std::to_string(id(i)) + " does not exist");
      o(i) = get(id(i));
    }
    return out;
  }
};

py::dict explain_dict(const ObjectExplain& e) {
  py::list levels;
  for (int k = 0; k < e.level_count; ++k) {
    const LevelExplain& l = e.levels[k];
    levels.append(py::dict("score"_a = l.score, "band"_a = l.band, "orientation"_a = l.orientation,
                           "frequency_cpd"_a = l.frequency_cpd, "threshold"_a = l.threshold));
  }
  return py::dict(
      "level"_a = e.level, "distance_m"_a = e.distance_m, "angular_diameter_deg"_a = e.angular_diameter_deg,
      "eccentricity_deg"_a = e.eccentricity_deg, "image_velocity_deg_s"_a = e.image_velocity_deg_s,
      "retinal_velocity_deg_s"_a = e.retinal_velocity_deg_s, "view"_a = e.view, "levels"_a = levels);
}

}  // namespace

std::shared_ptr<OwnedProfile> profile_from_file(const std::string& path) {
  return open_owned(io::read_file(path), path);  // io::Error: acuity.FileError, a ValueError
}

void bind_scheduler(py::module_ m) {
  py::class_<OwnedProfile, std::shared_ptr<OwnedProfile>>(
      m, "Profile", "A validated profile (.acuity blob). Build with Profile.from_bytes or Profile.load.")
      .def_static("from_bytes", &profile_from_bytes, "data"_a,
                  "Validate and wrap profile bytes (ValueError when bad).")
      .def_static("load", &profile_from_file, "path"_a,
                  "Read and validate a .acuity file (ValueError when bad).")
      .def_property_readonly("level_count", [](const OwnedProfile& p) { return p.view.meta.level_count; })
      .def_property_readonly("view_count", [](const OwnedProfile& p) { return p.view.meta.view_count; })
      .def_property_readonly("orientation_count",
                             [](const OwnedProfile& p) { return p.view.meta.orientation_count; })
      .def_property_readonly("band_count", [](const OwnedProfile& p) { return p.view.meta.band_count; })
      .def_property_readonly("size_bytes", [](const OwnedProfile& p) { return p.blob.size; })
      .def_property_readonly(
          "sphere", [](const OwnedProfile& p) { return get_array<4, float>(p.view.meta.sphere); },
          "bounding sphere: centre xyz, radius [object units]")
      .def_property_readonly("triangles",
                             [](const OwnedProfile& p) {
                               std::vector<std::uint32_t> t;
                               for (std::uint32_t k = 0; k < p.view.meta.level_count; ++k)
                                 t.push_back(p.view.levels[k].triangles);
                               return t;
                             })
      .def_property_readonly(
          "geometric_error",
          [](const OwnedProfile& p) {
            std::vector<float> t;
            for (std::uint32_t k = 0; k < p.view.meta.level_count; ++k)
              t.push_back(p.view.levels[k].geometric_error);
            return t;
          },
          "Hausdorff distance to level 0 per level [object diameters]")
      .def_property_readonly(
          "bands",
          [](const OwnedProfile& p) {
            return std::vector<float>(p.view.bands, p.view.bands + p.view.meta.band_count);
          },
          "band centres [cycles per object diameter]")
      .def_property_readonly(
          "orientations",
          [](const OwnedProfile& p) {
            return std::vector<float>(p.view.orientations,
                                      p.view.orientations + p.view.meta.orientation_count);
          },
          "orientations [deg]")
      .def_property_readonly(
          "lost",
          [](const OwnedProfile& p) {
            const auto& m = p.view.meta;
            py::array_t<float> a({py::ssize_t(m.level_count - 1), py::ssize_t(m.view_count),
                                  py::ssize_t(m.orientation_count), py::ssize_t(m.band_count)});
            std::memcpy(a.mutable_data(), p.view.lost, a.size() * sizeof(float));
            return a;
          },
          "lost contrast, shape (levels - 1, views, orientations, bands); index 0 is level 1")
      .def_property_readonly(
          "detail",
          [](const OwnedProfile& p) -> py::object {
            const auto& m = p.view.meta;
            if (!p.view.detail) return py::none();
            const std::vector<py::ssize_t> shape{py::ssize_t(m.level_count - 1), py::ssize_t(m.view_count),
                                                 py::ssize_t(m.orientation_count), py::ssize_t(m.band_count)};
            py::array_t<float> area(shape), offset(shape), turn(shape);
            for (py::ssize_t i = 0; i < area.size(); ++i) {
              area.mutable_data()[i] = detail_area(p.view.detail[i]);
              offset.mutable_data()[i] = detail_frequency_octaves(p.view.detail[i]);
              turn.mutable_data()[i] = detail_turn(p.view.detail[i]);
            }
            return py::make_tuple(area, offset, turn);
          },
          "the optional Detail section decoded, (area [fraction of the diameter squared], frequency offset\n"
          "[octaves], turn [orientation spacings]) shaped as lost, or None")
      .def("to_bytes", [](const OwnedProfile& p) {
        return py::bytes(static_cast<const char*>(p.blob.data()), p.blob.size);
      });

  py::enum_<SelectionRule> rules(m, "SelectionRule");
  for (const RuleInfo& r : selection_rules()) {  // the scheduler's one list; '-' is not a Python name
    std::string name = r.name;
    std::replace(name.begin(), name.end(), '-', '_');
    rules.value(name.c_str(), r.rule, r.help);
  }
  py::enum_<ViewBlend>(m, "ViewBlend").value("nearest", ViewBlend::Nearest).value("max3", ViewBlend::Max3);
  py::enum_<Evaluation>(m, "Evaluation",
                        "How the perceptual rule evaluates thresholds (see acuity/scheduler.hpp).")
      .value("tabulated", Evaluation::Tabulated)
      .value("exact", Evaluation::Exact);

  py::class_<SchedulerConfig>(m, "SchedulerConfig", "Scheduler settings (see acuity/scheduler.hpp).")
      .def(py::init<>())
      .def_readwrite("max_objects", &SchedulerConfig::max_objects)
      .def_readwrite("max_profiles", &SchedulerConfig::max_profiles)
      .def_readwrite("rule", &SchedulerConfig::rule)
      .def_readwrite("evaluation", &SchedulerConfig::evaluation)
      .def_readwrite("params", &SchedulerConfig::params)
      .def_readwrite("area_law", &SchedulerConfig::area_law,
                     "threshold raised by Rovamo's area law at each pooled loss's extent (Default, "
                     "Geisler-Perry, Kelly-Daly, stela-csf)")
      .def_readwrite("view_blend", &SchedulerConfig::view_blend)
      .def_readwrite("quality", &SchedulerConfig::quality)
      .def_readwrite("fallback_level", &SchedulerConfig::fallback_level)
      .ACUITY_ARRAY_PROPERTY(SchedulerConfig, tabulated_biases, float, kMaxTabulatedBiases,
                             "per-object biases with tables of their own besides 1 (0: unused)")
      .def_readwrite("min_gaze_confidence", &SchedulerConfig::min_gaze_confidence)
      .def_readwrite("gaze_uncertainty_deg", &SchedulerConfig::gaze_uncertainty_deg)
      .def_readwrite("no_gaze_radius_deg", &SchedulerConfig::no_gaze_radius_deg)
      .def_readwrite("hysteresis_margin", &SchedulerConfig::hysteresis_margin)
      .def_readwrite("hysteresis_seconds", &SchedulerConfig::hysteresis_seconds,
                     "[s] of the frames' dt; > 0 replaces hysteresis_frames")
      .def_readwrite("hysteresis_frames", &SchedulerConfig::hysteresis_frames,
                     "alias, used while hysteresis_seconds is 0")
      .def_readwrite("saccade_speed", &SchedulerConfig::saccade_speed)
      .def_readwrite("max_coarsen_wait_seconds", &SchedulerConfig::max_coarsen_wait_seconds,
                     "[s] of the frames' dt; > 0 replaces max_coarsen_wait")
      .def_readwrite("max_coarsen_wait", &SchedulerConfig::max_coarsen_wait,
                     "alias, used while max_coarsen_wait_seconds is 0")
      .def_readwrite("transition_seconds", &SchedulerConfig::transition_seconds)
      .def_readwrite("triangle_budget", &SchedulerConfig::triangle_budget)
      .def_readwrite("distance_scale", &SchedulerConfig::distance_scale)
      .def_readwrite("pixel_error", &SchedulerConfig::pixel_error)
      .def_readwrite("keep_scores", &SchedulerConfig::keep_scores)
      .def_readwrite("max_views", &SchedulerConfig::max_views, "views a frame may carry (View)")
      .def_readwrite("max_view_classes", &SchedulerConfig::max_view_classes,
                     "levels per object besides the eyes' (view_levels)")
      .def_property(
          "model", [](const SchedulerConfig& c) { return std::string(to_string(c.model)); },
          [](SchedulerConfig& c, const std::string& name) {
            if (!parse_threshold_model(name.c_str(), &c.model))
              throw py::value_error("unknown model '" + name + "'");
          },
          threshold_model_doc());

  py::class_<Eye>(
      m, "Eye",
      "One eye: world position [m], orientation quaternion xyzw (looks along -Z), FOV half-angles [deg].")
      .def(py::init<>())
      .ACUITY_ARRAY_PROPERTY(Eye, position, double, 3, "world [m]")
      .ACUITY_ARRAY_PROPERTY(Eye, orientation, float, 4, "unit quaternion x y z w, eye to world")
      .ACUITY_ARRAY_PROPERTY(Eye, fov_deg, float, 4, "left (<0), right, up, down (<0) [deg]")
      .ACUITY_ARRAY_PROPERTY(Eye, viewport, std::uint32_t, 2, "width, height [px]")
      .ACUITY_ARRAY_PROPERTY(Eye, velocity, float, 3, "world [m/s]")
      .ACUITY_ARRAY_PROPERTY(Eye, angular_velocity, float, 3, "head rotation, world axis x speed [deg/s]");
  py::class_<Gaze>(m, "Gaze",
                   "Gaze of one eye: direction in eye space, validity, confidence, optional velocity.")
      .def(py::init<>())
      .ACUITY_ARRAY_PROPERTY(Gaze, direction, float, 3, "unit, eye space")
      .ACUITY_ARRAY_PROPERTY(Gaze, angular_velocity, float, 3, "eye-in-head rotation [deg/s]")
      .def_readwrite("confidence", &Gaze::confidence)
      .def_readwrite("valid", &Gaze::valid)
      .def_readwrite("has_velocity", &Gaze::has_velocity);
  py::class_<Frame>(m, "Frame", "One frame's input: one or two eyes, their gaze, and dt [s].")
      .def(py::init<>())
      .def_property(
          "eyes", [](const Frame& f) { return std::vector<Eye>(f.eyes, f.eyes + f.eye_count); },
          [](Frame& f, const std::vector<Eye>& eyes) {
            if (eyes.empty() || eyes.size() > 2) throw py::value_error("one or two eyes");
            for (std::size_t i = 0; i < eyes.size(); ++i) f.eyes[i] = eyes[i];
            f.eye_count = static_cast<std::uint32_t>(eyes.size());
          })
      .def_property(
          "gaze", [](const Frame& f) { return std::vector<Gaze>(f.gaze, f.gaze + f.eye_count); },
          [](Frame& f, const std::vector<Gaze>& gaze) {
            if (gaze.size() > 2) throw py::value_error("at most two gaze entries");
            for (std::size_t i = 0; i < gaze.size(); ++i) f.gaze[i] = gaze[i];
          })
      .def_readwrite("dt", &Frame::dt);

  py::enum_<ViewProjection>(m, "ViewProjection", "A view's projection (acuity::ViewProjection).")
      .value("perspective", ViewProjection::Perspective)
      .value("orthographic", ViewProjection::Orthographic);
  py::enum_<ViewRule>(m, "ViewRule", "How a view's levels are chosen (acuity::ViewRule).")
      .value("footprint", ViewRule::Footprint, "the coarsest level whose error covers <= pixel_error texels")
      .value("as_eye", ViewRule::AsEye, "the scheduler's rule for an eye without gaze (perspective)");
  py::class_<View>(m, "View",
                   "A view beyond the eyes: a shadow map's light view or a secondary camera (see "
                   "acuity/scheduler.hpp). Passed to run_frame / begin_frame as views=[...].")
      .def(py::init<>())
      .def_readwrite("view_class", &View::view_class, "< SchedulerConfig.max_view_classes")
      .def_readwrite("projection", &View::projection)
      .def_readwrite("rule", &View::rule)
      .def_readwrite("pixel_error", &View::pixel_error, "Footprint: allowed projected error [texels or px]")
      .ACUITY_ARRAY_PROPERTY(View, position, double, 3, "world [m]")
      .ACUITY_ARRAY_PROPERTY(View, orientation, float, 4, "unit quaternion x y z w, view to world")
      .ACUITY_ARRAY_PROPERTY(View, fov_deg, float, 4, "perspective: left (<0), right, up, down (<0) [deg]")
      .ACUITY_ARRAY_PROPERTY(View, extent_m, float, 4, "orthographic: left, right, top, bottom [m]")
      .ACUITY_ARRAY_PROPERTY(View, viewport, std::uint32_t, 2, "width, height [texels or px]");

  py::class_<ProfileTables>(m, "ProfileTables", "One profile's tables, from Scheduler.make_tables().")
      .def("__bool__", [](const ProfileTables& t) { return bool(t); })
      .def_property_readonly("nbytes", &ProfileTables::bytes, "Bytes of tables held (0 once installed).");
  py::class_<PyScheduler>(
      m, "Scheduler",
      "Per-frame perceptual LOD selection. Arrays are numpy: positions (N, 3) float64 [m],\n"
      "rotations (N, 4) quaternions xyzw, scales (N,), velocities (N, 3) [m/s].")
      .def(py::init<const SchedulerConfig&>(), "config"_a = SchedulerConfig{})
      .def(
          "add_profile",
          [](PyScheduler& s, std::shared_ptr<OwnedProfile> p, bool deferred) {
            const int index =
                deferred ? s.scheduler.add_profile_deferred(p->view) : s.scheduler.add_profile(p->view);
            if (index < 0) throw py::value_error("add_profile: max_profiles reached");
            s.profiles.push_back(std::move(p));
            return index;
          },
          "profile"_a, "deferred"_a = false,
          "Registers a profile; returns its index. deferred=True: its tables are not built (quick), and\n"
          "its objects are decided exactly until install_tables().")
      .def(
          "make_tables",
          [](const PyScheduler& s, int profile, std::optional<std::uint32_t> view) {
            ProfileTables t;
            const int v =
                !view ? Scheduler::kAllViews : static_cast<int>(std::min<std::uint32_t>(*view, INT32_MAX));
            {
              py::gil_scoped_release release;  // other Python threads run meanwhile (it is thread-safe)
              t = s.scheduler.make_tables(profile, v);
            }
            if (!t)
              throw py::value_error("make_tables: profile " + std::to_string(profile) +
                                    (view ? " view " + std::to_string(*view) : std::string()) +
                                    " was not added, or this scheduler keeps no tables");
            return t;
          },
          "profile_id"_a, "view"_a = py::none(),
          "The profile's tables, as add_profile builds them (tenths of a second for 32 views), or one\n"
          "view's (about 1/(view count) of that: those wanted_tables() lists). Thread-safe (releases\n"
          "the GIL): call it from worker threads, during frames too.")
      .def(
          "wanted_tables",
          [](PyScheduler& s) {
            std::vector<std::pair<int, std::uint32_t>> out;
            TablesWanted wanted[64];
            for (std::uint32_t n; (n = s.scheduler.wanted_tables(wanted)) > 0;)
              for (std::uint32_t i = 0; i < n; ++i) out.emplace_back(wanted[i].profile, wanted[i].view);
            return out;
          },
          "Between frames: [(profile_id, view)], the views objects were seen from without their tables\n"
          "since the last call (each listed once until dropped): make_tables(profile_id, view), then\n"
          "install_tables.")
      .def(
          "drop_idle_tables",
          [](PyScheduler& s, std::uint32_t frames) { return s.scheduler.drop_idle_tables(frames); },
          "frames"_a,
          "Between frames: frees the tables of the views no object has read in the last `frames`\n"
          "frames (0: all); their objects decide exactly until wanted_tables() lists them again.\n"
          "Returns the bytes freed. Every few seconds, not every frame (it reallocates what it keeps).")
      .def(
          "install_tables",
          [](PyScheduler& s, int profile, ProfileTables& tables) {
            if (!s.scheduler.install_tables(profile, std::move(tables)))
              throw py::value_error(
                  "install_tables: tables made for another profile or scheduler, used, or "
                  "profile " +
                  std::to_string(profile) + " has tables of their views");
          },
          "profile_id"_a, "tables"_a,
          "Installs make_tables(profile_id, ...)'s tables between frames (they are used up): from the\n"
          "next frame the profile's objects seen from their views decide as if it had been added\n"
          "without deferred.")
      .def(
          "table_bytes",
          [](const PyScheduler& s, int profile) {
            if (profile < 0 || std::size_t(profile) >= s.profiles.size())
              throw py::index_error("table_bytes: profile " + std::to_string(profile) + " was not added");
            return s.scheduler.table_bytes(profile);
          },
          "profile_id"_a,
          "Bytes of runtime tables this scheduler keeps for the profile (0 where it evaluates exactly).")
      .def("add_objects", &PyScheduler::add_objects, "profile"_a, "position"_a, "rotation"_a, "scale"_a,
           "Add N objects; returns their ids (uint32). All or nothing: a profile index that was not\n"
           "added raises IndexError, more objects than free capacity ValueError; then none is added.")
      .def(
          "remove_objects",
          [](PyScheduler& s, U32 ids) {
            s.require_alive(ids, "remove_objects");
            auto id = ids.unchecked<1>();
            for (py::ssize_t i = 0; i < ids.shape(0); ++i)
              for (py::ssize_t j = 0; j < i; ++j)
                if (id(i) == id(j))
                  throw py::value_error("remove_objects: id " + std::to_string(id(i)) +
                                        " is given twice; nothing was removed");
            for (py::ssize_t i = 0; i < ids.shape(0); ++i) s.scheduler.remove_object(id(i));
            s.live -= std::uint32_t(ids.shape(0));
          },
          "ids"_a, "All or nothing: raises IndexError for an id that is not live, removing none.")
      .def("set_transforms", &PyScheduler::set_transforms, "ids"_a, "position"_a, "rotation"_a, "scale"_a,
           "All or nothing: raises IndexError for an id that is not live, setting none.")
      .def("set_velocities", &PyScheduler::set_velocities, "ids"_a, "velocity"_a,
           "All or nothing: raises IndexError for an id that is not live, setting none.")
      .def(
          "set_clamps",
          [](PyScheduler& s, std::uint32_t id, std::uint8_t lo, std::uint8_t hi) {
            s.require_alive(id, "set_clamps");
            if (hi < lo) throw py::value_error("set_clamps: max_level < min_level");
            s.scheduler.set_clamps(id, lo, hi);
          },
          "id"_a, "min_level"_a, "max_level"_a)
      .def(
          "set_bias",
          [](PyScheduler& s, std::uint32_t id, float bias) {
            s.require_alive(id, "set_bias");
            if (!(bias > 0) || !std::isfinite(bias))
              throw py::value_error("set_bias: bias must be finite and > 0");
            s.scheduler.set_bias(id, bias);
          },
          "id"_a, "quality_bias"_a, "Multiply q for this object (> 1 coarser).")
      .def(
          "run_frame",
          [](PyScheduler& s, const Frame& f, const std::vector<View>& views) {
            if (s.in_frame) throw py::value_error("run_frame: a frame was begun and not ended");
            s.scheduler.run_frame(s.with_views(f, views, "run_frame"));
          },
          "frame"_a, "views"_a = std::vector<View>{},
          "begin_frame, update every object, end_frame. views: View objects beyond the eyes.")
      .def(
          "begin_frame",
          [](PyScheduler& s, const Frame& f, const std::vector<View>& views) {
            if (s.in_frame) throw py::value_error("begin_frame: the previous frame was not ended");
            s.scheduler.begin_frame(s.with_views(f, views, "begin_frame"));
            s.in_frame = true;
          },
          "frame"_a, "views"_a = std::vector<View>{})
      .def(
          "update",
          [](PyScheduler& s, std::uint32_t first, std::uint32_t count) {
            if (!s.in_frame) throw py::value_error("update: no frame begun");
            const std::uint32_t cap = s.scheduler.object_capacity();
            if (first < cap) s.scheduler.update(first, std::min(count, cap - first));
          },
          "first"_a, "count"_a, "Update objects [first, first + count) (clipped to the capacity); any split.")
      .def("end_frame",
           [](PyScheduler& s) {
             if (!s.in_frame) throw py::value_error("end_frame: no frame begun");
             s.scheduler.end_frame();
             s.in_frame = false;
           })
      .def_property_readonly("object_capacity",
                             [](const PyScheduler& s) { return s.scheduler.object_capacity(); })
      .def(
          "previous_level",
          [](const PyScheduler& s, std::uint32_t id) {
            s.require_alive(id, "previous_level");
            return s.scheduler.previous_level(id);
          },
          "id"_a, "The level this object fades from.")
      .def(
          "transition",
          [](const PyScheduler& s, std::uint32_t id) {
            s.require_alive(id, "transition");
            return s.scheduler.transition(id);
          },
          "id"_a, "Fade to the current level, 0..1 (1 = done).")
      .def(
          "transitions",
          [](const PyScheduler& s, U32 ids) {
            py::array_t<std::uint8_t> previous =
                s.per_object(ids, [&](ObjectId i) { return s.scheduler.previous_level(i); });
            py::array_t<float> fade(ids.shape(0));
            auto f = fade.mutable_unchecked<1>();
            auto id = ids.unchecked<1>();
            for (py::ssize_t i = 0; i < ids.shape(0); ++i) f(i) = s.scheduler.transition(id(i));
            return py::make_tuple(previous, fade);
          },
          "ids"_a, "(previous levels uint8, fades float32) per id.")
      .def(
          "levels",
          [](const PyScheduler& s, U32 ids) {
            return s.per_object(ids, [&](ObjectId i) { return s.scheduler.level(i); });
          },
          "ids"_a)
      .def(
          "view_levels",
          [](const PyScheduler& s, std::uint32_t view_class, U32 ids) {
            const std::uint8_t* level = s.scheduler.view_level_array(view_class);
            if (!level) throw py::value_error("view_levels: view_class not below max_view_classes");
            return s.per_object(ids, [&](ObjectId i) { return level[i]; });
          },
          "view_class"_a, "ids"_a, "Each id's level for a view class this frame (uint8).")
      .def(
          "flags",
          [](const PyScheduler& s, U32 ids) {
            return s.per_object(ids, [&](ObjectId i) { return s.scheduler.flags(i); });
          },
          "ids"_a)
      .def(
          "scores",
          [](const PyScheduler& s, std::uint32_t id) -> py::object {
            const float* sc = s.scheduler.scores(id);
            if (!sc) return py::none();
            return py::array_t<float>(kMaxLevels, sc);
          },
          "id"_a, "Every level's score this frame (config.keep_scores), else None.")
      .def(
          "explain",
          [](const PyScheduler& s, std::uint32_t id) -> py::object {
            ObjectExplain e;
            if (!s.scheduler.explain(id, &e)) return py::none();
            return explain_dict(e);
          },
          "id"_a)
      .def_property_readonly("stats", [](const PyScheduler& s) {
        const FrameStats& st = s.scheduler.stats();
        return py::dict("triangles"_a = st.triangles, "changed"_a = st.changed,
                        "budget_forced"_a = st.budget_forced, "invalid"_a = st.invalid,
                        "gaze_used"_a = st.gaze_used, "at_rest"_a = st.at_rest);
      });

  m.attr("FLAG_INVALID_INPUT") = int(kFlagInvalidInput);
  m.attr("FLAG_EYE_INSIDE") = int(kFlagEyeInside);
  m.attr("FLAG_NO_GAZE") = int(kFlagNoGaze);
  m.attr("FLAG_BUDGET_FORCED") = int(kFlagBudgetForced);
  m.attr("FLAG_CHANGED") = int(kFlagChanged);
  m.attr("FLAG_HELD") = int(kFlagHeld);
}

}  // namespace acuity::python
