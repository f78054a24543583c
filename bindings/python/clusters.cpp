// acuity.clusters: an object's cluster hierarchy (the .glb of `acuity lodgen --clusters`) with its
// per-group loss (measured: the Clusters section of `acuity profile` of that glb; or, the fallback,
// derived from a chain profile of the same mesh), and its cuts (Scheduler::select_cut) as numpy arrays.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "acuity/clusters.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/scheduler.hpp"
#include "bindings.hpp"

namespace py = pybind11;
using namespace pybind11::literals;

namespace acuity::python {
namespace {

// One cut: the mesh's vertices (all of them, object space), the drawn clusters' triangles and ids.
struct Cut {
  py::array_t<float> positions;
  py::array_t<float> normals;
  py::array_t<std::uint32_t> indices;
  py::array_t<std::uint32_t> clusters;
  std::uint64_t triangles = 0;
  std::uint32_t groups_evaluated = 0;
  std::uint32_t budget_coarsened = 0, budget_forced = 0;
  std::uint8_t flags = 0;
};

struct Hierarchy {
  std::shared_ptr<OwnedProfile> profile;
  lodgen::Mesh mesh;
  lodgen::ClusterHierarchy h;
  std::vector<std::uint32_t> roots, made;  // cluster_roots, cluster_made_index
  std::vector<float> lost;  // the provisional loss (a chain profile), else empty: loss reads the profile
  std::vector<float> ln_lost, ln_view_lost;  // their logs, which the cut reads (loss_logs)
  ClusterLoss loss;
  bool measured = false;
  std::vector<std::uint8_t> scratch;
  std::vector<CutCandidate> candidates;  // the triangle budget's scratch
  std::vector<std::uint32_t> drawn;
  ClusterView view() const { return {h.clusters, h.groups, roots, made}; }

  Cut cut(std::span<const std::uint32_t> ids, const CutResult* r) const {
    Cut c;
    const py::ssize_t n = py::ssize_t(mesh.vertex_count());
    c.positions = py::array_t<float>({n, py::ssize_t(3)});
    std::copy(mesh.positions.begin(), mesh.positions.end(), c.positions.mutable_data());
    c.normals = py::array_t<float>({mesh.normals.empty() ? py::ssize_t(0) : n, py::ssize_t(3)});
    std::copy(mesh.normals.begin(), mesh.normals.end(), c.normals.mutable_data());
    std::size_t triangles = 0;
    for (std::uint32_t id : ids) triangles += h.clusters[id].triangle_count;
    c.indices = py::array_t<std::uint32_t>({py::ssize_t(triangles), py::ssize_t(3)});
    c.clusters = py::array_t<std::uint32_t>(py::ssize_t(ids.size()));
    std::uint32_t* out = c.indices.mutable_data();
    std::uint32_t* cl = c.clusters.mutable_data();
    for (std::uint32_t id : ids) {
      *cl++ = id;
      const Cluster& k = h.clusters[id];
      out =
          std::copy_n(&h.indices[3 * std::size_t(k.first_triangle)], 3 * std::size_t(k.triangle_count), out);
    }
    c.triangles = triangles;
    if (r) {
      c.groups_evaluated = r->groups_evaluated;
      c.budget_coarsened = r->budget_coarsened;
      c.budget_forced = r->budget_forced;
      c.flags = r->flags;
    }
    return c;
  }

  Cut finest() const {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t c = 0; c < h.clusters.size() && h.clusters[c].refined == kNoGroup; ++c)
      ids.push_back(c);
    return cut(ids, nullptr);
  }

  // A one-object scheduler at this quality and model, its frame begun with the eye and gaze.
  static std::unique_ptr<Scheduler> begun(const Eye& eye, const Gaze& gaze, float quality,
                                          const std::string& model, float dt,
                                          float hysteresis_seconds = 0.0f) {
    SchedulerConfig c;
    c.max_objects = 1;
    c.max_profiles = 1;
    c.evaluation = Evaluation::Exact;
    c.quality = quality;
    c.model = model_from(model);
    c.hysteresis_seconds = hysteresis_seconds;
    if (!(quality > 0) || !std::isfinite(quality))
      throw py::value_error("select: quality must be finite and > 0");
    if (!(dt >= 0) || !std::isfinite(dt)) throw py::value_error("select: dt must be finite and >= 0");
    auto s = std::make_unique<Scheduler>(c);
    Frame f;
    f.eyes[0] = eye;
    f.gaze[0] = gaze;
    f.dt = dt;
    s->begin_frame(f);
    return s;
  }
  static ObjectTransform placed(const std::array<double, 3>& position,
                                const std::array<float, 4>& orientation, float scale) {
    ObjectTransform t;
    for (int k = 0; k < 3; ++k) t.position[k] = position[std::size_t(k)];
    for (int k = 0; k < 4; ++k) t.rotation[k] = orientation[std::size_t(k)];
    t.scale = scale;
    return t;
  }

  Cut select(const Eye& eye, const Gaze& gaze, const std::array<double, 3>& position,
             const std::array<float, 4>& orientation, float scale, const std::array<float, 3>& velocity,
             float quality, const std::string& model, const py::object& memory, float dt,
             float hysteresis_seconds, std::uint64_t triangle_budget) {
    if (!(hysteresis_seconds >= 0) || !std::isfinite(hysteresis_seconds))
      throw py::value_error("select: hysteresis_seconds must be finite and >= 0");
    const std::unique_ptr<Scheduler> s = begun(eye, gaze, quality, model, dt, hysteresis_seconds);
    std::span<CutGroupMemory> remembered;
    if (!memory.is_none()) {  // the caller's bytes (new_memory()), stepped one frame of dt
      auto a = memory.cast<py::array_t<std::uint8_t>>();
      if (!a.writeable() || !(a.flags() & py::array::c_style) || std::size_t(a.nbytes()) != memory_bytes() ||
          reinterpret_cast<std::uintptr_t>(a.data()) % alignof(CutGroupMemory) != 0)
        throw py::value_error("select: memory must be new_memory()'s array (writable uint8, " +
                              std::to_string(memory_bytes()) + " bytes)");
      remembered = {reinterpret_cast<CutGroupMemory*>(a.mutable_data()), h.groups.size()};
    }
    const CutResult r = s->select_cut(view(), loss, placed(position, orientation, scale), velocity.data(),
                                      remembered, CutBudget{triangle_budget, candidates}, scratch, drawn);
    if (r.status != CutStatus::Ok) throw py::value_error(std::string("select: ") + to_string(r.status));
    return cut(std::span<const std::uint32_t>(drawn.data(), r.clusters), &r);
  }
  std::size_t memory_bytes() const { return h.groups.size() * sizeof(CutGroupMemory); }

  py::dict explain(const Eye& eye, const Gaze& gaze, const std::array<double, 3>& position,
                   const std::array<float, 4>& orientation, float scale, const std::array<float, 3>& velocity,
                   float quality, const std::string& model) {
    const std::unique_ptr<Scheduler> s = begun(eye, gaze, quality, model, 0.0f);
    std::vector<GroupExplain> out(h.groups.size());
    const CutStatus st =
        s->explain_cut(view(), loss, placed(position, orientation, scale), velocity.data(), scratch, out);
    if (st != CutStatus::Ok) throw py::value_error(std::string("explain: ") + to_string(st));
    const py::ssize_t G = py::ssize_t(out.size());
    py::array_t<float> score(G), frequency(G), threshold(G), distance(G), eccentricity(G);
    py::array_t<std::uint8_t> band(G), eye_index(G), flags(G), visible(G);
    for (py::ssize_t g = 0; g < G; ++g) {
      const GroupExplain& x = out[std::size_t(g)];
      score.mutable_data()[g] = x.score;
      band.mutable_data()[g] = x.band;
      eye_index.mutable_data()[g] = x.eye;
      flags.mutable_data()[g] = x.flags;
      visible.mutable_data()[g] = x.visible;
      frequency.mutable_data()[g] = x.frequency_cpd;
      threshold.mutable_data()[g] = x.threshold;
      distance.mutable_data()[g] = x.distance_m;
      eccentricity.mutable_data()[g] = x.eccentricity_deg;
    }
    return py::dict("score"_a = score, "band"_a = band, "eye"_a = eye_index, "flags"_a = flags,
                    "visible"_a = visible, "frequency_cpd"_a = frequency, "threshold"_a = threshold,
                    "distance_m"_a = distance, "eccentricity_deg"_a = eccentricity);
  }
};

std::shared_ptr<Hierarchy> load(const std::string& glb_path, const std::string& profile_path,
                                const py::object& view_cells) {
  auto out = std::make_shared<Hierarchy>();
  lodgen::Scene scene = lodgen::load_scene(glb_path);  // io::Error, lodgen::InputError: ValueErrors
  std::size_t m = 0;
  while (m < scene.clusters.size() && scene.clusters[m].empty()) ++m;
  if (m == scene.clusters.size())
    throw py::value_error(glb_path +
                          ": no mesh with a cluster hierarchy (ACUITY_cluster_hierarchy); make one "
                          "with `acuity lodgen MESH --clusters -o OUT.glb`");
  out->mesh = std::move(scene.meshes[m]);
  out->h = std::move(scene.clusters[m]);
  out->profile = profile_from_file(profile_path);
  const Profile& p = out->profile->view;
  out->roots = cluster_roots(out->h.clusters);
  out->made = cluster_made_index(out->h.clusters, out->h.groups.size());
  out->scratch.resize(out->h.groups.size());
  out->candidates.resize(out->h.groups.size());
  out->drawn.resize(out->h.clusters.size());
  const GroupLossStatus measured = measured_group_loss(p, out->h.clusters, out->h.groups, &out->loss);
  if (measured == GroupLossStatus::OtherHierarchy)
    throw py::value_error(profile_path + ": its Clusters section measured another hierarchy than " +
                          glb_path + "'s (group count or hash differ): profile this glb (`acuity profile " +
                          glb_path + " -o OUT.acuity`)");
  out->measured = measured == GroupLossStatus::Measured;
  if (out->measured && !view_cells.is_none()) {  // the caller's choice over measured_group_loss's
    const Profile& pr = out->profile->view;
    const std::size_t V = view_cells.cast<bool>() && pr.cluster_view_lost ? pr.cluster_views.view_count : 0;
    out->loss.view_directions = std::span<const float>(pr.cluster_view_directions, 3 * V);
    out->loss.view_lost =
        std::span<const float>(pr.cluster_view_lost, out->h.groups.size() * V * pr.clusters.band_count);
  }
  if (!out->measured) {
    if (p.levels[0].triangles != out->h.finest_triangles())
      throw py::value_error(profile_path + ": its level 0 has " + std::to_string(p.levels[0].triangles) +
                            " triangles, the hierarchy's finest mesh " +
                            std::to_string(out->h.finest_triangles()) +
                            ": profile a chain of the same mesh (`acuity lodgen MESH -o CHAIN.glb`, then "
                            "`acuity profile CHAIN.glb`)");
    out->lost = provisional_group_loss(p, out->h.groups, &out->loss);
    out->loss.lost = out->lost;
  }
  out->ln_lost = loss_logs(out->loss.lost);
  out->ln_view_lost = loss_logs(out->loss.view_lost);
  out->loss.ln_lost = out->ln_lost;
  out->loss.ln_view_lost = out->ln_view_lost;
  return out;
}

}  // namespace

void bind_clusters(py::module_ m) {
  m.doc() =
      "Detail that follows the gaze inside one object (issue 48): a cluster hierarchy and its cuts.\n\n"
      "h = acuity.clusters.load(glb_path, profile_path): the .glb of `acuity lodgen MESH --clusters`, and\n"
      "its profile (`acuity profile OUT.glb`), which measured what each group loses (h.measured); or\n"
      "the fallback, the profile of a chain of the same mesh (`acuity lodgen MESH -o CHAIN.glb`), from\n"
      "which each group's loss is derived (acuity/clusters.hpp, provisional_group_loss).\n"
      "h.finest() and h.select(eye, gaze, position,\n"
      "orientation, scale=1.0, velocity=(0, 0, 0), quality=1.0) return a Cut: .positions (float32 n x 3,\n"
      "object space: every vertex of the mesh), .indices (uint32 m x 3: the drawn triangles), .clusters\n"
      "(uint32: the drawn cluster ids).";
  py::class_<Cut>(m, "Cut", "One cut of a hierarchy: the mesh's vertices and the drawn clusters' triangles.")
      .def_readonly("positions", &Cut::positions, "float32 (n, 3): every vertex of the mesh, object space")
      .def_readonly(
          "normals", &Cut::normals,
          "float32 (n, 3): every vertex's unit normal, object space ((0, 3) when the mesh has none)")
      .def_readonly("indices", &Cut::indices, "uint32 (m, 3): the drawn triangles, into positions")
      .def_readonly("clusters", &Cut::clusters, "uint32: the drawn cluster ids")
      .def_readonly("triangles", &Cut::triangles, "drawn triangles (m)")
      .def_readonly("groups_evaluated", &Cut::groups_evaluated, "groups whose thresholds the walk evaluated")
      .def_readonly("budget_coarsened", &Cut::budget_coarsened,
                    "visible groups the triangle budget coarsened (select(..., triangle_budget=))")
      .def_readonly("budget_forced", &Cut::budget_forced,
                    "... of them with a score > 1: a visible loss (FLAG_BUDGET_FORCED)")
      .def_readonly("flags", &Cut::flags, "FLAG_* bits: FLAG_EYE_INSIDE, FLAG_NO_GAZE, FLAG_BUDGET_FORCED");
  py::class_<Hierarchy, std::shared_ptr<Hierarchy>>(m, "Hierarchy",
                                                    "A mesh's cluster hierarchy with its per-group loss.")
      .def("finest", &Hierarchy::finest, "The finest cut: the mesh as lodgen wrote it (level 0).")
      .def(
          "new_memory",
          [](const Hierarchy& h) {
            py::array_t<std::uint8_t> a(py::ssize_t(h.memory_bytes()));
            std::fill_n(a.mutable_data(), a.size(), std::uint8_t(0));
            return a;
          },
          "What select() remembers of each group between frames (CutGroupMemory; zeroed: nothing\n"
          "remembered), one per object: pass it as select(..., memory=m, dt=frame seconds,\n"
          "hysteresis_seconds=...) every frame.")
      .def("explain", &Hierarchy::explain, "eye"_a, "gaze"_a, "position"_a, "orientation"_a, "scale"_a = 1.0f,
           "velocity"_a = std::array<float, 3>{0, 0, 0}, "quality"_a = 1.0f, "model"_a = "default",
           "Why select() (without memory) decides as it does (Scheduler::explain_cut): per group, arrays\n"
           "'score' (max over bands of lost / (q CT); <= 1 invisible), 'band' (the limiting band, into\n"
           "bands), 'eye', 'flags' (FLAG_EYE_INSIDE, FLAG_NO_GAZE), 'visible' (1: refined), and that\n"
           "band's 'frequency_cpd', 'threshold' (CT at q = 1), 'distance_m' and 'eccentricity_deg'.")
      .def("select", &Hierarchy::select, "eye"_a, "gaze"_a, "position"_a, "orientation"_a, "scale"_a = 1.0f,
           "velocity"_a = std::array<float, 3>{0, 0, 0}, "quality"_a = 1.0f, "model"_a = "default",
           "memory"_a = py::none(), "dt"_a = 0.0f, "hysteresis_seconds"_a = 0.0f, "triangle_budget"_a = 0,
           "The cut for one eye (acuity.Eye) and its gaze (acuity.Gaze) with the object at `position`\n"
           "[m, world], turned by `orientation` (unit quaternion x y z w, object to world), scaled by\n"
           "`scale`, moving at `velocity` [m/s]; the perceptual rule's `model` (a threshold model name) at "
           "quality q,\n"
           "evaluated exactly (Scheduler::select_cut). memory (new_memory()'s array): hysteresis per group,\n"
           "this call one frame of dt seconds after the last: a group refines at once and coarsens once it\n"
           "has been invisible for hysteresis_seconds; None: each group decided at once. triangle_budget\n"
           "(0: none): when the cut draws more, the visible groups of least score per triangle saved are\n"
           "coarsened first, a whole group at a time (crack-free), until it draws at most that or only\n"
           "groups an eye is inside are left (Cut.budget_coarsened, .budget_forced). ValueError for "
           "invalid input\n"
           "(non-finite or non-unit transform, scale <= 0, an invalid eye, a wrong memory).")
      .def_property_readonly("cluster_count", [](const Hierarchy& h) { return h.h.clusters.size(); })
      .def_property_readonly("group_count", [](const Hierarchy& h) { return h.h.groups.size(); })
      .def_property_readonly("finest_triangles", [](const Hierarchy& h) { return h.h.finest_triangles(); })
      .def_property_readonly(
          "group_spheres",
          [](const Hierarchy& h) {
            py::array_t<float> a({py::ssize_t(h.h.groups.size()), py::ssize_t(4)});
            float* o = a.mutable_data();
            for (const ClusterGroup& g : h.h.groups) {
              *o++ = g.center[0];
              *o++ = g.center[1];
              *o++ = g.center[2];
              *o++ = g.radius;
            }
            return a;
          },
          "float32 (groups, 4): each group's bounding sphere, centre xyz and radius [object units]")
      .def_property_readonly(
          "loss",
          [](const Hierarchy& h) {
            py::array_t<float> a({py::ssize_t(h.h.groups.size()), py::ssize_t(h.loss.bands_cpod.size())});
            std::copy(h.loss.lost.begin(), h.loss.lost.end(), a.mutable_data());
            return a;
          },
          "float32 (groups, bands): each group's lost contrast per band (measured or provisional)")
      .def_property_readonly(
          "bands",
          [](const Hierarchy& h) {
            py::array_t<float> a(py::ssize_t(h.loss.bands_cpod.size()));
            std::copy(h.loss.bands_cpod.begin(), h.loss.bands_cpod.end(), a.mutable_data());
            return a;
          },
          "float32: the loss's band centres [cycles per diameter]")
      .def_property_readonly(
          "view_directions",
          [](const Hierarchy& h) {
            py::array_t<float> a({py::ssize_t(h.loss.view_directions.size() / 3), py::ssize_t(3)});
            std::copy(h.loss.view_directions.begin(), h.loss.view_directions.end(), a.mutable_data());
            return a;
          },
          "float32 (cells, 3): the loss's view cells, unit directions from the object towards the eye, "
          "object\n"
          "space ((0, 3): the loss has no cells, the profile has no ClusterViews section)")
      .def_property_readonly(
          "view_loss",
          [](const Hierarchy& h) {
            const py::ssize_t V = py::ssize_t(h.loss.view_directions.size() / 3);
            py::array_t<float> a({py::ssize_t(h.h.groups.size()), V, py::ssize_t(h.loss.bands_cpod.size())});
            std::copy(h.loss.view_lost.begin(), h.loss.view_lost.end(), a.mutable_data());
            return a;
          },
          "float32 (groups, cells, bands): each group's lost contrast per view cell and band (the cut reads\n"
          "the cell the eye is in); each at most `loss`'s value")
      .def_readonly("measured", &Hierarchy::measured,
                    "True when the loss is the profile's measurement (its Clusters section), False when it "
                    "is derived from a chain profile (provisional_group_loss)")
      .def_property_readonly(
          "diameter", [](const Hierarchy& h) { return h.loss.diameter; },
          "the profile's bounding-sphere diameter [object units]");
  m.def("load", &load, "glb_path"_a, "profile_path"_a, "view_cells"_a = py::none(),
        "A hierarchy from `acuity lodgen MESH --clusters -o OUT.glb` (its first mesh with one) and its\n"
        "profile (`acuity profile OUT.glb -o OUT.acuity`: each group measured), or the profile of a chain\n"
        "of the same mesh (`acuity lodgen MESH -o CHAIN.glb`, `acuity profile CHAIN.glb -o CHAIN.acuity`:\n"
        "the loss derived, the fallback); ValueError when the glb has no hierarchy, the profile measured\n"
        "another hierarchy, or a chain profile's level 0 is another mesh. view_cells: None reads the\n"
        "profile's loss per view cell (its ClusterViews section) when it was measured from at least 162\n"
        "directions per group (acuity::kMinCellSamples), as C++ and the C ABI do; True whenever the\n"
        "section is there (an experiment: from fewer directions the cells do not bound the loss); False\n"
        "never (each group's loss over all views).");
}

}  // namespace acuity::python
