#pragma once
// acuity/transform.hpp — an engine's world matrix as the ObjectTransform the scheduler takes
// (acuity/scheduler.hpp): for engines that keep 4x4 matrices (OpenSceneGraph, glTF node trees).
#include "acuity/scheduler.hpp"

namespace acuity {

// `matrix`: 16 doubles, column-major (column c is matrix[4c .. 4c+3]; the translation is
// matrix[12 .. 14]), the layout of glTF, GLM and OpenSceneGraph's Matrixd::ptr(). Returns the
// translation [m], the rotation as a unit quaternion, and the largest axis scale (the bounding
// sphere scales by it). A mirror (negative determinant) keeps a rotation: the third axis is flipped,
// which leaves the bounding sphere unchanged. A zero-length axis counts as that unit axis.
ObjectTransform transform_from_matrix(const double matrix[16]);

}  // namespace acuity
