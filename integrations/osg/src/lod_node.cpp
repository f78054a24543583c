#include <osgUtil/CullVisitor>

#include "acuity/osg/kit.hpp"

namespace acuity::osg {

LodNode::LodNode(const LodNode& other, const ::osg::CopyOp& op)
    : ::osg::Group(other, op) {}  // a copy is not an object until added

LodNode::~LodNode() {
  ::osg::ref_ptr<Kit> kit;
  if (kit_.lock(kit)) kit->remove(this);
}

LodNode::Drawn LodNode::drawn() const {
  std::lock_guard<std::mutex> lock(drawn_mutex_);
  return drawn_;
}

LodNode::DrawnInView LodNode::drawn_in_view() const {
  std::lock_guard<std::mutex> lock(drawn_mutex_);
  return drawn_in_view_;
}

void LodNode::traverse(::osg::NodeVisitor& nv) {
  ::osg::ref_ptr<Kit> kit;
  const bool live = id_ != kInvalidObject && kit_.lock(kit);
  if (nv.getVisitorType() == ::osg::NodeVisitor::CULL_VISITOR && live && nv.getFrameStamp()) {
    auto* cv = nv.asCullVisitor();
    const ::osg::Camera* camera = cv ? cv->getCurrentCamera() : nullptr;
    kit->run_frame(*nv.getFrameStamp(), camera);
    const Scheduler& s = kit->scheduler();
    if (const int view_class = kit->view_class_of(camera); view_class >= 0) {  // a shadow or mirror pass
      const std::uint8_t level = s.view_level_array(std::uint32_t(view_class))[id_];
      if (level < getNumChildren()) getChild(level)->accept(nv);
      std::lock_guard<std::mutex> lock(drawn_mutex_);
      drawn_in_view_ = {nv.getFrameStamp()->getFrameNumber(), std::uint32_t(view_class), level};
      return;
    }
    const std::uint8_t level = s.level(id_), previous = s.previous_level(id_);
    const float fade = Kit::quantise_fade(s.transition(id_));
    const bool both = fade < 1.0f && previous != level && previous < getNumChildren();
    auto draw = [&](std::uint8_t k, float f, bool outgoing) {
      if (k >= getNumChildren()) return;
      if (cv) {
        cv->pushStateSet(kit->level_state(k));
        cv->pushStateSet(kit->fade_state(f, outgoing));
      }
      getChild(k)->accept(nv);
      if (cv) {
        cv->popStateSet();
        cv->popStateSet();
      }
    };
    draw(level, both ? fade : 1.0f, false);
    if (both) draw(previous, fade, true);
    std::lock_guard<std::mutex> lock(drawn_mutex_);
    const std::uint32_t number = nv.getFrameStamp()->getFrameNumber();
    drawn_.culls = drawn_.frame == number ? drawn_.culls + 1 : 1;
    drawn_.frame = number;
    drawn_.level = level;
    drawn_.previous = previous;
    drawn_.fade = both ? fade : 1.0f;
    drawn_.both = both;
    return;
  }
  // Not an acuity object (no kit, or its kit is gone): the finest level is the active one.
  if (nv.getVisitorType() == ::osg::NodeVisitor::CULL_VISITOR ||
      nv.getTraversalMode() == ::osg::NodeVisitor::TRAVERSE_ACTIVE_CHILDREN) {
    const std::uint8_t level = live ? kit->scheduler().level(id_) : 0;
    if (level < getNumChildren()) getChild(level)->accept(nv);
    return;
  }
  ::osg::Group::traverse(nv);
}

}  // namespace acuity::osg
