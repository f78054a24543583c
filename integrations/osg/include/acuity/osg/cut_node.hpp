#pragma once
// acuity/osg/cut_node.hpp — one object drawn as its cluster cut (acuity/clusters.hpp; docs/design.md
// section 6, "Cluster cuts"): detail that follows the gaze inside the object. The node's one child
// is a Geometry over the hierarchy's vertices whose one DrawElementsUInt holds the cut's triangles,
// rebuilt when the cut changes.
//
//   auto* node = new acuity::osg::CutNode(kit, geometry, std::move(hierarchy));  // kit: Kit, already attached
//   parent->addChild(node);                                 // anywhere under transforms
//
// Each frame the first cull traversal that reaches it (after the kit's frame, Kit::run_frame) takes
// the node's world transform from its node path (translation, rotation, the largest axis scale:
// acuity::transform_from_matrix) and asks Scheduler::select_cut for the cut under this frame's eyes
// and gaze, with hysteresis and saccade gating per group kept in the node (the scheduler's timing);
// the object counts as still (no velocity). The cut is the same for every camera of the frame
// (stereo: both eyes decide it). Thread-safe for OSG's threading models: under a mutex, once per
// frame number; the geometry and its DrawElementsUInt are DYNAMIC. The kit links only the runtime
// and OpenSceneGraph; loading a hierarchy from lodgen's glTF is the application's (acuity::osg_gltf
// or lodgen's reader).
#include <cstdint>
#include <mutex>
#include <vector>

#include <osg/Geometry>
#include <osg/Group>
#include <osg/PrimitiveSet>

#include "acuity/osg/kit.hpp"

namespace acuity::osg {

class CutNode : public ::osg::Group {
 public:
  // What the node draws from: the hierarchy's index array (three per triangle, into the geometry's
  // vertices) and records, laid out as ClusterView requires (check_cluster_records passes), and
  // what each group loses per band (ClusterLoss: bands_cpod, diameter, lost).
  struct Hierarchy {
    std::vector<std::uint32_t> indices;
    std::vector<Cluster> clusters;
    std::vector<ClusterGroup> groups;
    std::vector<float> bands_cpod, lost;
    float diameter = 0;
  };
  // geometry: the vertices (and any attributes) of the hierarchy; its primitive sets are replaced by
  // the cut's. Throws std::invalid_argument when the hierarchy fails check_cluster_records, its
  // indices leave the geometry's vertices or its loss has the wrong size.
  CutNode(Kit* kit, ::osg::Geometry* geometry, Hierarchy hierarchy);
  ::osg::Object* cloneType() const override { return nullptr; }  // one hierarchy and memory per node
  ::osg::Object* clone(const ::osg::CopyOp&) const override { return nullptr; }
  bool isSameKindAs(const ::osg::Object* obj) const override {
    return dynamic_cast<const CutNode*>(obj) != nullptr;
  }
  const char* className() const override { return "CutNode"; }
  const char* libraryName() const override { return "acuity"; }

  // What the last frame's cut was (for debug views and tests).
  struct Drawn {
    std::uint32_t frame = 0xffffffffu;  // frame number of the cut
    CutResult cut;                      // select_cut's result
    std::uint32_t indices = 0;          // in the DrawElementsUInt drawn
    std::uint32_t rebuilds = 0;         // times the index buffer was rebuilt (the cut changed)
  };
  Drawn drawn() const;
  // The cluster ids of the last cut, in select_cut's order.
  std::vector<std::uint32_t> drawn_clusters() const;
  const Hierarchy& hierarchy() const { return h_; }
  ::osg::Geometry* geometry() const { return geometry_.get(); }

  // In a cull traversal: the frame's cut, then the geometry; other visitors traverse the geometry
  // with the last cut (the finest before the first).
  void traverse(::osg::NodeVisitor& nv) override;

 private:
  void rebuild(std::uint32_t count);  // the index buffer from cut_[0 .. count)

  ::osg::observer_ptr<Kit> kit_;
  ::osg::ref_ptr<::osg::Geometry> geometry_;
  ::osg::ref_ptr<::osg::DrawElementsUInt> elements_;
  Hierarchy h_;
  std::vector<std::uint32_t> roots_;
  std::vector<CutGroupMemory> memory_;
  std::vector<std::uint8_t> scratch_;
  std::vector<std::uint32_t> cut_, next_;  // the drawn cut, and this frame's
  ::osg::NodePath path_;                   // reused by the transform walk
  mutable std::mutex mutex_;
  Drawn drawn_;
};

}  // namespace acuity::osg
