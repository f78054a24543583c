#pragma once
// Geometry the simulation's parts share (private to sim/): degrees, head space, object centres.
#include <cmath>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "acuity/sim/scene.hpp"
#include "acuity/sim/tracks.hpp"

namespace acuity::sim {

constexpr double kPi = 3.14159265358979323846, kDeg = 180.0 / kPi;

// A world point in the head's space.
inline glm::dvec3 to_head(const HeadPose& h, const glm::dvec3& world_point) {
  return glm::inverse(h.orientation) * (world_point - h.position);
}

// The angle between two directions [deg].
inline double angle_deg(const glm::dvec3& a, const glm::dvec3& b) {
  return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)) * kDeg;
}

// The world centre of an asset's bounding sphere placed by t.
inline glm::dvec3 world_centre(const Asset& a, const ObjectTransform& t) {
  const glm::dquat q(t.rotation[3], t.rotation[0], t.rotation[1], t.rotation[2]);
  const glm::dvec3 c(a.profile.meta.sphere[0], a.profile.meta.sphere[1], a.profile.meta.sphere[2]);
  return glm::dvec3(t.position[0], t.position[1], t.position[2]) + q * (double(t.scale) * c);
}

}  // namespace acuity::sim
