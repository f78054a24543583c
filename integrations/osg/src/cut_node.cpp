// CutNode (acuity/osg/cut_node.hpp): a cluster cut drawn through one DrawElementsUInt.
#include "acuity/osg/cut_node.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include <osgUtil/CullVisitor>

#include "acuity/transform.hpp"

namespace acuity::osg {

CutNode::CutNode(Kit* kit, ::osg::Geometry* geometry, Hierarchy hierarchy)
    : kit_(kit), geometry_(geometry), h_(std::move(hierarchy)) {
  if (!kit || !geometry) throw std::invalid_argument("CutNode: a kit and a geometry are needed");
  if (const std::string fault = check_cluster_records(h_.clusters, h_.groups, h_.indices.size() / 3);
      !fault.empty() || h_.indices.size() % 3)
    throw std::invalid_argument("CutNode: " + (fault.empty() ? "indices are not whole triangles" : fault));
  const ::osg::Array* vertices = geometry->getVertexArray();
  const std::uint32_t vertex_count = vertices ? vertices->getNumElements() : 0;
  for (std::uint32_t i : h_.indices)
    if (i >= vertex_count)
      throw std::invalid_argument("CutNode: index " + std::to_string(i) + " leaves the geometry's " +
                                  std::to_string(vertex_count) + " vertices");
  if (h_.lost.size() != h_.groups.size() * h_.bands_cpod.size() || h_.bands_cpod.empty() ||
      !(h_.diameter > 0))
    throw std::invalid_argument("CutNode: the loss needs groups x bands values, a band and a diameter > 0");
  roots_ = cluster_roots(h_.clusters);
  memory_.assign(h_.groups.size(), CutGroupMemory{});
  scratch_.assign(h_.groups.size(), 0);
  cut_.reserve(h_.clusters.size());
  next_.assign(h_.clusters.size(), 0);
  elements_ = new ::osg::DrawElementsUInt(GL_TRIANGLES);
  elements_->setDataVariance(::osg::Object::DYNAMIC);
  geometry_->setDataVariance(::osg::Object::DYNAMIC);
  geometry_->removePrimitiveSet(0, geometry_->getNumPrimitiveSets());
  geometry_->addPrimitiveSet(elements_.get());
  for (std::uint32_t c = 0; c < h_.clusters.size() && h_.clusters[c].refined == kNoGroup; ++c) next_[c] = c;
  std::uint32_t finest = 0;
  while (finest < h_.clusters.size() && h_.clusters[finest].refined == kNoGroup) ++finest;
  rebuild(finest);
  addChild(geometry_.get());
}

CutNode::Drawn CutNode::drawn() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return drawn_;
}

std::vector<std::uint32_t> CutNode::drawn_clusters() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cut_;
}

void CutNode::rebuild(std::uint32_t count) {
  cut_.assign(next_.begin(), next_.begin() + count);
  ::osg::DrawElementsUInt& e = *elements_;
  e.clear();
  for (std::uint32_t c : cut_) {
    const Cluster& k = h_.clusters[c];
    const std::uint32_t* t = &h_.indices[3 * std::size_t(k.first_triangle)];
    e.insert(e.end(), t, t + 3 * std::size_t(k.triangle_count));
  }
  e.dirty();
  geometry_->dirtyBound();
  drawn_.indices = std::uint32_t(e.size());
  ++drawn_.rebuilds;
}

void CutNode::traverse(::osg::NodeVisitor& nv) {
  ::osg::ref_ptr<Kit> kit;
  if (nv.getVisitorType() == ::osg::NodeVisitor::CULL_VISITOR && nv.getFrameStamp() && kit_.lock(kit)) {
    auto* cv = nv.asCullVisitor();
    kit->run_frame(*nv.getFrameStamp(), cv ? cv->getCurrentCamera() : nullptr);
    std::lock_guard<std::mutex> lock(mutex_);
    const std::uint32_t number = nv.getFrameStamp()->getFrameNumber();
    if (drawn_.frame != number) {
      drawn_.frame = number;
      // The world transform from the first parents up (as the kit reads a LodNode's): a cull's node
      // path may begin at a camera, whose view matrix is not the object's.
      path_.clear();
      for (::osg::Node* p = this; p && path_.size() <= 4096;
           p = p->getNumParents() ? p->getParent(0) : nullptr)
        path_.push_back(p);
      std::reverse(path_.begin(), path_.end());
      const ::osg::Matrixd m = ::osg::computeLocalToWorld(path_);
      const ClusterLoss loss{h_.bands_cpod, h_.diameter, h_.lost};
      drawn_.cut =
          kit->scheduler().select_cut({h_.clusters, h_.groups, roots_}, loss, transform_from_matrix(m.ptr()),
                                      nullptr, memory_, scratch_, next_);
      const std::uint32_t n = std::min<std::uint32_t>(drawn_.cut.clusters, std::uint32_t(next_.size()));
      if (n != cut_.size() || !std::equal(cut_.begin(), cut_.end(), next_.begin())) rebuild(n);
    }
  }
  ::osg::Group::traverse(nv);
}

}  // namespace acuity::osg
