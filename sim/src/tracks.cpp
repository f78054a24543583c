#include "acuity/sim/tracks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "acuity/file.hpp"

namespace acuity::sim {
namespace {

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw std::runtime_error(where + ": " + what);
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r"), b = s.find_last_not_of(" \t\r");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string field;
  while (std::getline(ss, field, ',')) out.push_back(trim(field));
  if (!line.empty() && line.back() == ',') out.emplace_back();
  return out;
}

Table read_csv(const std::string& path, std::istream& in) {
  Table t;
  t.source = path;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const std::string s = trim(line);
    if (s.empty() || s[0] == '#') continue;
    const std::vector<std::string> fields = split(s);
    const std::string where = path + ":" + std::to_string(number);
    if (t.columns.empty()) {
      for (const std::string& f : fields)
        if (f.empty()) fail(where, "the header has an empty column name");
      t.columns = fields;
      continue;
    }
    if (fields.size() != t.columns.size())
      fail(where,
           std::to_string(fields.size()) + " fields, the header has " + std::to_string(t.columns.size()));
    std::vector<double> row;
    for (std::size_t c = 0; c < fields.size(); ++c) {
      double v = 0;
      const char* end = fields[c].data() + fields[c].size();
      const auto r = std::from_chars(fields[c].data(), end, v);
      if (r.ec != std::errc() || r.ptr != end || !std::isfinite(v))
        fail(where, "column '" + t.columns[c] + "': '" + fields[c] + "' is not a finite number");
      row.push_back(v);
    }
    t.rows.push_back(std::move(row));
  }
  if (t.columns.empty()) fail(path, "no header line (CSV needs one naming the columns)");
  return t;
}

Table read_json(const std::string& path, std::istream& in) {
  Table t;
  t.source = path;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) { fail(path, std::string("not valid JSON: ") + e.what()); }
  if (!j.is_array()) fail(path, "expected an array of objects with numeric fields");
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string where = path + ": row " + std::to_string(i);
    if (!j[i].is_object()) fail(where, "is not an object");
    if (t.columns.empty())
      for (auto it = j[i].begin(); it != j[i].end(); ++it) t.columns.push_back(it.key());
    if (j[i].size() != t.columns.size())
      fail(where,
           "has " + std::to_string(j[i].size()) + " fields, row 0 has " + std::to_string(t.columns.size()));
    std::vector<double> row;
    for (const std::string& c : t.columns) {
      if (!j[i].contains(c)) fail(where, "has no '" + c + "'");
      const auto& v = j[i][c];
      if (!v.is_number() || !std::isfinite(v.get<double>()))
        fail(where, "'" + c + "' is not a finite number");
      row.push_back(v.get<double>());
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

// Frame f's position in the table: the row before and the weight of the row after.
struct Resampler {
  const Table& table;
  int t_column;
  std::size_t row = 0;
  Resampler(const Table& t) : table(t), t_column(t.column("t", true)) {
    if (t.rows.empty()) fail(t.source, "has no rows");
    for (std::size_t i = 1; i < t.rows.size(); ++i)
      if (!(t.rows[i][std::size_t(t_column)] > t.rows[i - 1][std::size_t(t_column)]))
        fail(t.source, "row " + std::to_string(i) + ": t = " +
                           std::to_string(t.rows[i][std::size_t(t_column)]) + " does not increase");
  }
  double at(double time) {  // advances monotonically
    const auto T = [&](std::size_t i) { return table.rows[i][std::size_t(t_column)]; };
    while (row + 1 < table.rows.size() && T(row + 1) <= time) ++row;
    if (row + 1 >= table.rows.size() || time <= T(row)) return 0;
    return (time - T(row)) / (T(row + 1) - T(row));
  }
  double value(int column, double w) const {
    const double a = table.rows[row][std::size_t(column)];
    if (w == 0 || row + 1 >= table.rows.size()) return a;
    return a + w * (table.rows[row + 1][std::size_t(column)] - a);
  }
};

}  // namespace

const char* to_string(GazePhase p) {
  switch (p) {
    case GazePhase::Fixation:
      return "fixation";
    case GazePhase::Saccade:
      return "saccade";
    case GazePhase::Pursuit:
      return "pursuit";
    case GazePhase::Blink:
      return "blink";
    case GazePhase::Recorded:
      return "recorded";
  }
  return "?";
}

int Table::column(const std::string& name, bool required) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return int(i);
  if (required) fail(source, "has no column '" + name + "'");
  return -1;
}

Table parse_table(const std::string& text, const std::string& source, bool json) {
  // A UTF-8 byte order mark (spreadsheets write one) is not part of the first column's name.
  const bool bom = text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  return json ? read_json(source, in) : read_csv(source, in);
}

Table read_table(const std::string& path) {
  const Blob blob = io::read_file(path);  // a regular file only: a FIFO or device is refused, not waited on
  const std::string text(static_cast<const char*>(blob.data()), blob.size);
  return parse_table(text, path, std::filesystem::path(path).extension().string() == ".json");
}

std::vector<HeadPose> head_path_from(const Table& table, double fps, std::size_t frames) {
  Resampler r(table);
  int c[7];
  const char* names[7] = {"x", "y", "z", "qx", "qy", "qz", "qw"};
  for (int i = 0; i < 7; ++i) c[i] = table.column(names[i], true);
  auto pose = [&](std::size_t row) {
    glm::dquat q(table.rows[row][std::size_t(c[6])], table.rows[row][std::size_t(c[3])],
                 table.rows[row][std::size_t(c[4])], table.rows[row][std::size_t(c[5])]);
    if (!(glm::length(q) > 1e-6))
      fail(table.source, "row " + std::to_string(row) + ": the orientation quaternion is zero");
    return glm::normalize(q);
  };
  for (std::size_t i = 0; i < table.rows.size(); ++i) pose(i);
  std::vector<HeadPose> out(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    const double w = r.at(double(f) / fps);
    for (int k = 0; k < 3; ++k) out[f].position[k] = r.value(c[k], w);
    const glm::dquat a = pose(r.row);
    out[f].orientation = w > 0 ? glm::normalize(glm::slerp(a, pose(r.row + 1), w)) : a;
  }
  return out;
}

std::vector<GazeSample> gaze_trace_from(const Table& table, double fps, std::size_t frames) {
  Resampler r(table);
  const int x = table.column("x", true), y = table.column("y", true), z = table.column("z", true);
  const int conf = table.column("confidence", false);
  std::vector<GazeSample> out(frames);
  for (std::size_t f = 0; f < frames; ++f) {
    const double w = r.at(double(f) / fps);
    const glm::dvec3 d(r.value(x, w), r.value(y, w), r.value(z, w));
    double c = conf < 0 ? 1.0 : table.rows[r.row][std::size_t(conf)];
    if (conf >= 0 && w > 0)
      c = std::min(c, table.rows[r.row + 1][std::size_t(conf)]);  // a blink is not interpolated away
    if (glm::length(d) > 1e-9)
      out[f].direction = glm::normalize(d);
    else
      c = 0;  // no direction: no gaze
    out[f].confidence = float(std::clamp(c, 0.0, 1.0));
  }
  return out;
}

std::string head_path_csv(const std::vector<HeadPose>& head, double fps, std::size_t frames) {
  std::ostringstream h;
  h.precision(17);
  h << "t,x,y,z,qx,qy,qz,qw\n";
  for (std::size_t i = 0; i < frames; ++i) {
    const HeadPose& p = head[i];
    h << double(i) / fps << "," << p.position.x << "," << p.position.y << "," << p.position.z << ","
      << p.orientation.x << "," << p.orientation.y << "," << p.orientation.z << "," << p.orientation.w
      << "\n";
  }
  return h.str();
}

std::string gaze_trace_csv(const std::vector<GazeSample>& gaze, double fps, std::size_t frames) {
  std::ostringstream g;
  g.precision(17);
  g << "t,x,y,z,confidence\n";
  for (std::size_t i = 0; i < frames; ++i) {
    const GazeSample& z = gaze[i];
    g << double(i) / fps << "," << z.direction.x << "," << z.direction.y << "," << z.direction.z << ","
      << z.confidence << "\n";
  }
  return g.str();
}

}  // namespace acuity::sim
