#include "acuity/transform.hpp"

#include <algorithm>
#include <cmath>

namespace acuity {

ObjectTransform transform_from_matrix(const double m[16]) {
  ObjectTransform t;
  for (int k = 0; k < 3; ++k) t.position[k] = m[12 + k];
  double r[3][3];  // r[column][row]: the unit axes
  double largest = 0;
  for (int c = 0; c < 3; ++c) {
    const double* axis = m + 4 * c;
    const double len = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    largest = std::max(largest, len);
    for (int k = 0; k < 3; ++k) r[c][k] = len > 0 ? axis[k] / len : double(c == k);
  }
  const double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
                     r[1][0] * (r[0][1] * r[2][2] - r[0][2] * r[2][1]) +
                     r[2][0] * (r[0][1] * r[1][2] - r[0][2] * r[1][1]);
  if (det < 0)
    for (double& v : r[2]) v = -v;
  // The quaternion of a rotation matrix from its largest component (numerically stable).
  const double four_sq_minus_1[4] = {r[0][0] + r[1][1] + r[2][2], r[0][0] - r[1][1] - r[2][2],
                                     r[1][1] - r[0][0] - r[2][2], r[2][2] - r[0][0] - r[1][1]};
  const int big = int(std::max_element(four_sq_minus_1, four_sq_minus_1 + 4) - four_sq_minus_1);
  const double b = std::sqrt(std::max(0.0, four_sq_minus_1[big]) + 1) * 0.5, mult = 0.25 / b;
  double w = 0, x = 0, y = 0, z = 0;
  switch (big) {
    case 0:
      w = b, x = (r[1][2] - r[2][1]) * mult, y = (r[2][0] - r[0][2]) * mult, z = (r[0][1] - r[1][0]) * mult;
      break;
    case 1:
      w = (r[1][2] - r[2][1]) * mult, x = b, y = (r[0][1] + r[1][0]) * mult, z = (r[2][0] + r[0][2]) * mult;
      break;
    case 2:
      w = (r[2][0] - r[0][2]) * mult, x = (r[0][1] + r[1][0]) * mult, y = b, z = (r[1][2] + r[2][1]) * mult;
      break;
    default:
      w = (r[0][1] - r[1][0]) * mult, x = (r[2][0] + r[0][2]) * mult, y = (r[1][2] + r[2][1]) * mult, z = b;
  }
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  t.rotation[0] = float(x / n);
  t.rotation[1] = float(y / n);
  t.rotation[2] = float(z / n);
  t.rotation[3] = float(w / n);
  t.scale = float(largest);
  return t;
}

}  // namespace acuity
