#pragma once
// Head paths and gaze traces as files: a small table reader (CSV or JSON), the resampling of
// tracks to frames, and the writers of the CSV the readers take back. Units as in acuity/scheduler.hpp: metres, seconds; the head looks along its
// local -Z with +Y up; gaze directions are unit vectors in head space.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace acuity::sim {

// A table of numbers with named columns: CSV with a header line, or JSON: an array of flat objects.
// Throws std::runtime_error naming the file and the line (CSV) or row (JSON) at fault.
struct Table {
  std::string source;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  int column(const std::string& name, bool required) const;  // -1 when absent and not required
};
Table read_table(const std::string& path);
// The same from text; source names it in messages.
Table parse_table(const std::string& text, const std::string& source, bool json);

struct HeadPose {
  glm::dvec3 position{0.0};            // world [m]
  glm::dquat orientation{1, 0, 0, 0};  // head to world (w, x, y, z as GLM stores it)
};
struct GazeSample {
  glm::dvec3 direction{0, 0, -1};  // unit, head space
  float confidence = 1;            // 0: no gaze (blink, tracking lost)
};
enum class GazePhase : std::uint8_t { Fixation, Saccade, Pursuit, Blink, Recorded };
const char* to_string(GazePhase phase);

// Sampled tracks: columns t,x,y,z,qx,qy,qz,qw (head path) and t,x,y,z[,confidence] (gaze), with
// t strictly increasing [s]. Resampled to frames (linear, normalised; held past the ends).
std::vector<HeadPose> head_path_from(const Table& table, double fps, std::size_t frames);
std::vector<GazeSample> gaze_trace_from(const Table& table, double fps, std::size_t frames);

// The inverse: the first `frames` poses (samples) at t = frame / fps as CSV text with those
// columns, numbers with 17 significant digits (read back exactly).
std::string head_path_csv(const std::vector<HeadPose>& head, double fps, std::size_t frames);
std::string gaze_trace_csv(const std::vector<GazeSample>& gaze, double fps, std::size_t frames);

}  // namespace acuity::sim
