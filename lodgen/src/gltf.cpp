// glTF input (tinygltf) with every accessor bounds-checked, and LOD output with MSFT_lod.
#include "acuity/lodgen/gltf.hpp"

#include "acuity/lodgen/formats.hpp"

#include <stb_image.h>
#include <stb_image_write.h>
#include <sys/stat.h>
#include <tiny_gltf.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <sstream>

#include "acuity/file.hpp"

namespace acuity::lodgen {
namespace {

using tinygltf::Accessor;
using tinygltf::Model;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw InputError(where + ": " + what);
}

// Everything decoded or read counts against LoadLimits::max_total_bytes.
struct Budget {
  std::uint64_t left = 0;
  std::string path;
  void charge(std::uint64_t bytes, const std::string& what) {
    if (bytes > left)
      throw InputError(path + ": " + what + " needs " + std::to_string(bytes) + " more bytes than the " +
                       "load limit max_total_bytes leaves (" + std::to_string(left) + ")");
    left -= bytes;
  }
};

// a + b and a * b, or InputError naming `what` when the result does not fit in 64 bits.
std::uint64_t checked_add(std::uint64_t a, std::uint64_t b, const std::string& what) {
  std::uint64_t r = 0;
  if (__builtin_add_overflow(a, b, &r))
    fail(what, "offset arithmetic overflows (" + std::to_string(a) + " + " + std::to_string(b) + ")");
  return r;
}
std::uint64_t checked_mul(std::uint64_t a, std::uint64_t b, const std::string& what) {
  std::uint64_t r = 0;
  if (__builtin_mul_overflow(a, b, &r))
    fail(what, "size arithmetic overflows (" + std::to_string(a) + " x " + std::to_string(b) + ")");
  return r;
}

// Where an accessor's elements are: every offset, length, count and stride checked, in overflow-safe
// arithmetic, against the bytes the buffer really holds.
struct Span {
  const unsigned char* base = nullptr;
  std::size_t stride = 0, count = 0;
};

// The bytes bufferView `index` holds, checked against its buffer.
const unsigned char* view_bytes(const Model& m, int index, const std::string& at) {
  if (index < 0 || index >= int(m.bufferViews.size())) fail(at, "no valid bufferView");
  const tinygltf::BufferView& v = m.bufferViews[std::size_t(index)];
  const std::string view = at + ", bufferView " + std::to_string(index);
  if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) fail(view, "names no valid buffer");
  const std::vector<unsigned char>& buf = m.buffers[std::size_t(v.buffer)].data;
  if (checked_add(v.byteOffset, v.byteLength, view) > buf.size())
    fail(view, "bytes " + std::to_string(v.byteOffset) + " + " + std::to_string(v.byteLength) +
                   " reach past its buffer's " + std::to_string(buf.size()) + " bytes");
  return buf.data() + v.byteOffset;
}

Span accessor_span(const Model& m, const Accessor& a, std::size_t element, const std::string& at) {
  if (a.sparse.isSparse) fail(at, "sparse accessors are not supported");
  const unsigned char* bytes = view_bytes(m, a.bufferView, at);
  const tinygltf::BufferView& v = m.bufferViews[std::size_t(a.bufferView)];
  const std::string view = at + ", bufferView " + std::to_string(a.bufferView);
  const std::size_t stride = v.byteStride ? v.byteStride : element;
  if (stride < element)
    fail(view, "byteStride " + std::to_string(stride) + " is smaller than an element (" +
                   std::to_string(element) + " bytes)");
  Span s;
  s.stride = stride;
  s.count = a.count;
  if (a.count == 0) return s;
  const std::uint64_t need =
      checked_add(checked_add(a.byteOffset, checked_mul(a.count - 1, stride, at), at), element, at);
  if (need > v.byteLength)
    fail(at, std::to_string(a.count) + " elements from byteOffset " + std::to_string(a.byteOffset) +
                 " need " + std::to_string(need) + " bytes; its bufferView has " +
                 std::to_string(v.byteLength));
  s.base = bytes + a.byteOffset;  // both sums were checked above
  return s;
}

// Reads accessor `index` as `components` floats per element (FLOAT, or normalised integers).
std::vector<float> read_floats(const Model& m, int index, int components, const std::string& where,
                               Budget& budget) {
  if (index < 0 || index >= int(m.accessors.size()))
    fail(where, "accessor " + std::to_string(index) + " does not exist");
  const Accessor& a = m.accessors[std::size_t(index)];
  const std::string at = where + ", accessor " + std::to_string(index);
  if (tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)) != components)
    fail(at, "expected " + std::to_string(components) + " components per element");
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (csize <= 0) fail(at, "unknown component type");
  const Span span = accessor_span(m, a, std::size_t(csize) * std::size_t(components), at);
  budget.charge(checked_mul(span.count, std::size_t(components) * sizeof(float), at), at);
  std::vector<float> out(span.count * std::size_t(components));
  for (std::size_t i = 0; i < span.count; ++i)
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = span.base + i * span.stride + std::size_t(c) * std::size_t(csize);
      float x;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          std::memcpy(&x, p, 4);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          x = float(*p) / 255.0f;
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          std::uint16_t s;
          std::memcpy(&s, p, 2);
          x = float(s) / 65535.0f;
          break;
        }
        default:
          fail(at,
               "component type " + std::to_string(a.componentType) + " is not a float or normalised type");
      }
      if (!std::isfinite(x)) fail(at, "element " + std::to_string(i) + " is not finite");
      out[i * std::size_t(components) + std::size_t(c)] = x;
    }
  return out;
}

std::vector<std::uint32_t> read_indices(const Model& m, int index, std::size_t vertex_count,
                                        const std::string& where, Budget& budget) {
  if (index < 0) {  // non-indexed: 0, 1, 2, ...
    budget.charge(checked_mul(vertex_count, 4, where), where + ", implicit indices");
    std::vector<std::uint32_t> out(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) out[i] = std::uint32_t(i);
    return out;
  }
  if (index >= int(m.accessors.size()))
    fail(where, "index accessor " + std::to_string(index) + " does not exist");
  const Accessor& a = m.accessors[std::size_t(index)];
  const std::string at = where + ", index accessor " + std::to_string(index);
  if (a.type != TINYGLTF_TYPE_SCALAR) fail(at, "must be scalar");
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (csize != 1 && csize != 2 && csize != 4) fail(at, "indices must be unsigned byte, short or int");
  const Span span = accessor_span(m, a, std::size_t(csize), at);
  budget.charge(checked_mul(span.count, 4, at), at);
  std::vector<std::uint32_t> out(span.count);
  for (std::size_t i = 0; i < span.count; ++i) {
    std::uint32_t x = 0;
    std::memcpy(&x, span.base + i * span.stride, std::size_t(csize));  // little-endian
    if (x >= vertex_count)
      fail(at, "index " + std::to_string(x) + " at element " + std::to_string(i) + " is out of range");
    out[i] = x;
  }
  return out;
}

std::array<double, 16> local_matrix(const tinygltf::Node& n) {
  std::array<double, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  if (n.matrix.size() == 16) {
    std::copy(n.matrix.begin(), n.matrix.end(), m.begin());
    return m;
  }
  double t[3] = {0, 0, 0}, r[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1};
  if (n.translation.size() == 3) std::copy(n.translation.begin(), n.translation.end(), t);
  if (n.rotation.size() == 4) std::copy(n.rotation.begin(), n.rotation.end(), r);
  if (n.scale.size() == 3) std::copy(n.scale.begin(), n.scale.end(), s);
  const double x = r[0], y = r[1], z = r[2], w = r[3];
  const double rot[9] = {
      1 - 2 * (y * y + z * z), 2 * (x * y + z * w),     2 * (x * z - y * w),
      2 * (x * y - z * w),     1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
      2 * (x * z + y * w),     2 * (y * z - x * w),     1 - 2 * (x * x + y * y)};  // columns
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) m[c * 4 + k] = rot[c * 3 + k] * s[c];
  for (int k = 0; k < 3; ++k) m[12 + k] = t[k];
  return m;
}

// The extension that stores a primitive's cluster hierarchy (docs/lodgen.md).
constexpr const char* kClusterExtension = "ACUITY_cluster_hierarchy";
constexpr std::size_t kClusterBytes = 16, kGroupBytes = 32;  // on-disk records (cluster_hierarchy.hpp)
static_assert(sizeof(Cluster) == kClusterBytes, "Cluster is copied as its four uint32");

// A whole number in [0, max] under `key` of the extension object.
std::uint64_t extension_count(const tinygltf::Value& ext, const char* key, std::uint64_t max,
                              const std::string& at, const std::string& limit) {
  const double x =
      ext.IsObject() && ext.Has(key) && ext.Get(key).IsNumber() ? ext.Get(key).GetNumberAsDouble() : -1;
  if (!(x >= 0 && x == std::floor(x))) fail(at, std::string(key) + " is missing or not a whole number >= 0");
  if (x > double(max))
    fail(at, std::string(key) + " " + std::to_string(x) + " is more than the limit " + limit + " (" +
                 std::to_string(max) + ")");
  return std::uint64_t(x);
}

// The records of bufferView `key`: exactly count x record_bytes bytes.
const unsigned char* extension_records(const Model& m, const tinygltf::Value& ext, const char* key,
                                       std::uint64_t count, std::size_t record_bytes, const std::string& at,
                                       Budget& budget) {
  const std::uint64_t view = extension_count(ext, key, m.bufferViews.size(), at, "of the file's bufferViews");
  const unsigned char* bytes = view_bytes(m, int(std::min<std::uint64_t>(view, INT32_MAX)), at + ", " + key);
  const std::size_t length = m.bufferViews[std::size_t(view)].byteLength;
  if (length != count * record_bytes)
    fail(at, std::string(key) + " bufferView holds " + std::to_string(length) + " bytes, not " +
                 std::to_string(count) + " x " + std::to_string(record_bytes));
  budget.charge(length, at + ", " + key);
  return bytes;
}

ClusterHierarchy read_clusters(const Model& m, const tinygltf::Value& ext, const Mesh& mesh,
                               const std::string& where, const ClusterLimits& limits, Budget& budget) {
  const std::string at = where + ", " + kClusterExtension;
  const std::uint64_t clusters =
      extension_count(ext, "clusterCount", limits.max_clusters, at, "max_clusters");
  const std::uint64_t groups = extension_count(ext, "groupCount", limits.max_groups, at, "max_groups");
  ClusterHierarchy h;
  const unsigned char* c = extension_records(m, ext, "clusters", clusters, kClusterBytes, at, budget);
  const unsigned char* g = extension_records(m, ext, "groups", groups, kGroupBytes, at, budget);
  const std::uint64_t accessor =
      extension_count(ext, "indices", m.accessors.size(), at, "of the file's accessors");
  h.indices =
      read_indices(m, int(std::min<std::uint64_t>(accessor, INT32_MAX)), mesh.vertex_count(), at, budget);
  h.clusters.resize(clusters);
  for (std::size_t i = 0; i < clusters; ++i)  // little-endian, as read_indices assumes
    std::memcpy(&h.clusters[i], c + i * kClusterBytes, kClusterBytes);
  h.groups.resize(groups);
  for (std::size_t i = 0; i < groups; ++i) {
    ClusterGroup& x = h.groups[i];
    std::memcpy(x.center, g + i * kGroupBytes, 12);
    std::memcpy(&x.radius, g + i * kGroupBytes + 12, 4);
    std::memcpy(&x.error, g + i * kGroupBytes + 16, 4);
    std::memcpy(&x.first_member, g + i * kGroupBytes + 20, 4);
    std::memcpy(&x.member_count, g + i * kGroupBytes + 24, 4);
    std::memcpy(&x.level, g + i * kGroupBytes + 28, 4);
  }
  if (const std::string fault = check_cluster_hierarchy(h, mesh.vertex_count(), limits); !fault.empty())
    fail(at, fault);
  const std::size_t finest = 3 * h.finest_triangles();
  if (mesh.indices.size() != finest ||
      !std::equal(mesh.indices.begin(), mesh.indices.end(), h.indices.begin()))
    fail(at,
         "the primitive's indices are not the hierarchy's finest clusters (an engine without the extension "
         "would draw another mesh)");
  return h;
}

Scene convert(const Model& model, const std::string& path, const LoadLimits& limits, Budget& budget) {
  Scene scene;
  for (const tinygltf::Material& src : model.materials) {
    Material mat;
    mat.name = src.name;
    const auto& f = src.pbrMetallicRoughness.baseColorFactor;
    for (std::size_t k = 0; k < 4 && k < f.size(); ++k) mat.base_color[k] = float(f[k]);
    const int tex = src.pbrMetallicRoughness.baseColorTexture.index;
    if (tex >= 0 && tex < int(model.textures.size())) {
      const int source = model.textures[tex].source;
      if (source >= 0 && source < int(model.images.size())) {
        const tinygltf::Image& img = model.images[source];
        if (img.width > 0 && img.height > 0 && img.bits == 8 && img.component >= 1 && img.component <= 4 &&
            img.image.size() ==
                std::size_t(img.width) * std::size_t(img.height) * std::size_t(img.component)) {
          budget.charge(std::uint64_t(img.width) * std::uint64_t(img.height) * 4,
                        path + ": material '" + src.name + "' texture");
          mat.width = img.width;
          mat.height = img.height;
          mat.pixels.resize(std::size_t(img.width) * img.height * 4, 255);
          for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
            for (int c = 0; c < std::min(img.component, 4); ++c)
              mat.pixels[i * 4 + c] = img.image[i * img.component + c];
          if (img.component < 3)  // grey (+ alpha): spread the grey into RGB
            for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i) {
              mat.pixels[i * 4 + 1] = mat.pixels[i * 4 + 2] = mat.pixels[i * 4];
              mat.pixels[i * 4 + 3] = img.component == 2 ? img.image[i * 2 + 1] : 255;
            }
        }
      }
    }
    scene.materials.push_back(std::move(mat));
  }
  // Each triangle primitive becomes one Mesh; mesh_first[m] is glTF mesh m's first.
  std::vector<int> mesh_first, mesh_count;
  for (std::size_t mi = 0; mi < model.meshes.size(); ++mi) {
    mesh_first.push_back(int(scene.meshes.size()));
    const tinygltf::Mesh& src = model.meshes[mi];
    for (std::size_t pi = 0; pi < src.primitives.size(); ++pi) {
      const tinygltf::Primitive& prim = src.primitives[pi];
      const std::string where =
          path + ": mesh " + std::to_string(mi) + " ('" + src.name + "') primitive " + std::to_string(pi);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1)
        fail(where, "only triangle primitives are supported");
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail(where, "has no POSITION");
      Mesh m;
      m.positions = read_floats(model, pos->second, 3, where, budget);
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end())
        m.normals = read_floats(model, it->second, 3, where, budget);
      if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end())
        m.texcoords = read_floats(model, it->second, 2, where, budget);
      if ((!m.normals.empty() && m.normals.size() != m.positions.size()) ||
          (!m.texcoords.empty() && m.texcoords.size() / 2 != m.positions.size() / 3))
        fail(where, "attributes differ in length from POSITION");
      m.indices = read_indices(model, prim.indices, m.vertex_count(), where, budget);
      if (m.indices.size() % 3)
        fail(where, "index count " + std::to_string(m.indices.size()) + " is not a multiple of 3");
      m.material = prim.material >= 0 && prim.material < int(scene.materials.size()) ? prim.material : -1;
      const auto ext = prim.extensions.find(kClusterExtension);
      scene.clusters.push_back(ext == prim.extensions.end()
                                   ? ClusterHierarchy{}
                                   : read_clusters(model, ext->second, m, where, limits.clusters, budget));
      scene.meshes.push_back(std::move(m));
      scene.mesh_names.push_back(src.name.empty() ? "mesh" + std::to_string(mi) : src.name);
    }
    mesh_count.push_back(int(src.primitives.size()));
  }
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const tinygltf::Node& src = model.nodes[ni];
    Node n;
    n.name = src.name;
    n.matrix = local_matrix(src);
    for (double x : n.matrix)
      if (!std::isfinite(x)) fail(path + ": node " + std::to_string(ni), "transform is not finite");
    for (int c : src.children) {
      if (c < 0 || c >= int(model.nodes.size()))
        fail(path + ": node " + std::to_string(ni), "child " + std::to_string(c) + " does not exist");
      n.children.push_back(c);
    }
    if (src.mesh >= 0) {
      if (src.mesh >= int(model.meshes.size()))
        fail(path + ": node " + std::to_string(ni), "mesh " + std::to_string(src.mesh) + " does not exist");
      if (mesh_count[src.mesh] > 0) n.mesh = mesh_first[src.mesh];
    }
    if (auto it = src.extensions.find("MSFT_lod"); it != src.extensions.end() && it->second.Has("ids")) {
      const tinygltf::Value& ids = it->second.Get("ids");
      for (std::size_t i = 0; i < ids.ArrayLen(); ++i) n.lods.push_back(ids.Get(int(i)).GetNumberAsInt());
    }
    if (src.extras.Has("MSFT_screencoverage")) {
      const tinygltf::Value& c = src.extras.Get("MSFT_screencoverage");
      for (std::size_t i = 0; i < c.ArrayLen(); ++i)
        n.screen_coverage.push_back(c.Get(int(i)).GetNumberAsDouble());
    }
    if (src.extras.Has("acuity_geometric_error")) {
      const tinygltf::Value& e = src.extras.Get("acuity_geometric_error");
      for (std::size_t i = 0; i < e.ArrayLen(); ++i) {
        const double x = e.Get(int(i)).GetNumberAsDouble();
        if (!(x >= 0) || !std::isfinite(x))
          fail(path + ": node " + std::to_string(ni),
               "acuity_geometric_error[" + std::to_string(i) + "] is not a finite error >= 0");
        n.geometric_error.push_back(x);
      }
    }
    scene.nodes.push_back(std::move(n));
  }
  // Extra primitives of a multi-primitive mesh hang under the node as children.
  for (std::size_t ni = 0; ni < model.nodes.size(); ++ni) {
    const int gm = model.nodes[ni].mesh;
    if (gm < 0) continue;
    for (int p = 1; p < mesh_count[gm]; ++p) {
      Node extra;
      extra.name = scene.nodes[ni].name + "_primitive" + std::to_string(p);
      extra.mesh = mesh_first[gm] + p;
      scene.nodes[ni].children.push_back(int(scene.nodes.size()));
      scene.nodes.push_back(std::move(extra));
    }
  }
  const int s = model.defaultScene >= 0 ? model.defaultScene : 0;
  if (s < int(model.scenes.size())) {
    for (int r : model.scenes[s].nodes) {
      if (r < 0 || r >= int(model.nodes.size()))
        fail(path, "scene root " + std::to_string(r) + " does not exist");
      scene.roots.push_back(r);
    }
  } else {
    for (std::size_t i = 0; i < model.nodes.size(); ++i) scene.roots.push_back(int(i));
  }
  for (const Node& n : scene.nodes)
    for (int l : n.lods)
      if (l < 0 || l >= int(scene.nodes.size()))
        fail(path, "MSFT_lod names node " + std::to_string(l) + ", which does not exist");
  return scene;
}

// --- writing ---

struct BufferWriter {
  tinygltf::Model& model;
  std::vector<unsigned char>& data;
  int view(const void* bytes, std::size_t size, int target) {
    while (data.size() % 4) data.push_back(0);
    tinygltf::BufferView v;
    v.buffer = 0;
    v.byteOffset = data.size();
    v.byteLength = size;
    if (target) v.target = target;
    const auto* b = static_cast<const unsigned char*>(bytes);
    data.insert(data.end(), b, b + size);
    model.bufferViews.push_back(v);
    return int(model.bufferViews.size() - 1);
  }
  int accessor(const std::vector<float>& values, int components, bool bounds) {
    tinygltf::Accessor a;
    a.bufferView = view(values.data(), values.size() * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.count = values.size() / components;
    a.type = components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC2;
    if (bounds) {
      a.minValues.assign(components, std::numeric_limits<double>::max());
      a.maxValues.assign(components, std::numeric_limits<double>::lowest());
      for (std::size_t i = 0; i < values.size(); ++i) {
        a.minValues[i % components] = std::min(a.minValues[i % components], double(values[i]));
        a.maxValues[i % components] = std::max(a.maxValues[i % components], double(values[i]));
      }
    }
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
  }
  int indices(const std::vector<std::uint32_t>& values) {
    return index_accessor(view(values.data(), values.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                          values.size());
  }
  // The first `count` indices of bufferView `view`.
  int index_accessor(int view, std::size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.count = count;
    a.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
  }
};

// Level 0's primitive with a cluster hierarchy: its indices are the finest clusters', a prefix of
// one bufferView that holds every cluster's; the extension names that whole view's accessor and the
// records' bufferViews (docs/lodgen.md).
void write_clusters(BufferWriter& w, const ClusterHierarchy& h, tinygltf::Primitive& prim) {
  const int view = w.view(h.indices.data(), h.indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  prim.indices = w.index_accessor(view, 3 * h.finest_triangles());
  std::vector<unsigned char> clusters(h.clusters.size() * kClusterBytes),
      groups(h.groups.size() * kGroupBytes);
  for (std::size_t i = 0; i < h.clusters.size(); ++i)  // little-endian, as the reader takes them
    std::memcpy(&clusters[i * kClusterBytes], &h.clusters[i], kClusterBytes);
  for (std::size_t i = 0; i < h.groups.size(); ++i) {
    const ClusterGroup& x = h.groups[i];
    unsigned char* g = &groups[i * kGroupBytes];
    std::memcpy(g, x.center, 12);
    std::memcpy(g + 12, &x.radius, 4);
    std::memcpy(g + 16, &x.error, 4);
    std::memcpy(g + 20, &x.first_member, 4);
    std::memcpy(g + 24, &x.member_count, 4);
    std::memcpy(g + 28, &x.level, 4);
  }
  tinygltf::Value::Object ext;
  ext["indices"] = tinygltf::Value(w.index_accessor(view, h.indices.size()));
  ext["clusters"] = tinygltf::Value(w.view(clusters.data(), clusters.size(), 0));
  ext["clusterCount"] = tinygltf::Value(int(h.clusters.size()));
  ext["groups"] = tinygltf::Value(w.view(groups.data(), groups.size(), 0));
  ext["groupCount"] = tinygltf::Value(int(h.groups.size()));
  prim.extensions[kClusterExtension] = tinygltf::Value(ext);
}

void append_png(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<unsigned char>*>(context);
  const auto* b = static_cast<const unsigned char*>(data);
  out->insert(out->end(), b, b + size);
}

bool identity(const std::array<double, 16>& m) {
  for (int i = 0; i < 16; ++i)
    if (m[i] != (i % 5 == 0 ? 1.0 : 0.0)) return false;
  return true;
}

}  // namespace

namespace {

namespace fs = std::filesystem;

// Reads a whole regular file through acuity::io, within max_file_bytes and what the budget leaves
// (refused before reading), confined to `root` when it is not empty; charges the budget.
void read_within(const std::string& path, const std::string& root, const LoadLimits& limits, Budget& budget,
                 std::vector<unsigned char>* out) {
  io::ReadLimits l;
  l.root = root;
  l.max_bytes = std::min(limits.max_file_bytes, budget.left);
  l.max_bytes_name = limits.max_file_bytes <= budget.left ? "the load limit max_file_bytes"
                                                          : "the load limit max_total_bytes leaves";
  io::read_file(path, l, out);
  budget.left -= out->size();
}

// The JSON's nesting depth, scanned as text (strings skipped) so that no parser recurses into a
// hostile document: throws past `limit`.
void check_json_depth(const char* text, std::size_t size, std::uint32_t limit, const std::string& path) {
  std::uint32_t depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < size; ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\')
        ++i;
      else if (c == '"')
        in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > limit)
        throw InputError(path + ": JSON nested deeper than the load limit max_json_depth (" +
                         std::to_string(limit) + ")");
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
}

// A uri's file, resolved against `base` and required to stay inside `root` (both canonical).
// Returns "" and sets *why when the uri is refused. data: URIs never reach here.
std::string resolve_uri(const std::string& uri, const fs::path& base, const fs::path& root,
                        std::string* why) {
  if (uri.empty()) {
    *why = "is empty";
    return {};
  }
  if (uri.front() == '/' || uri.front() == '\\') {
    *why = "is an absolute path; only paths relative to the glTF are read";
    return {};
  }
  if (uri.find(':') != std::string::npos) {
    *why = "has a scheme (file:, http:, ...) or a drive; only relative paths and data: URIs are read";
    return {};
  }
  if (uri.find('%') != std::string::npos) {
    *why = "has %-escapes; write the path plainly";
    return {};
  }
  if (uri.find('\\') != std::string::npos) {
    *why = "has a backslash; use '/'";
    return {};
  }
  const fs::path lexical = (base / uri).lexically_normal();
  auto inside = [&](const fs::path& p) {
    const fs::path rel = p.lexically_relative(root);
    return !rel.empty() && *rel.begin() != ".." && rel != ".";
  };
  if (!inside(lexical)) {
    *why = "leaves the asset folder " + root.string() + " (see --asset-root)";
    return {};
  }
  try {
    return io::confine(lexical.string(), root.string());  // symbolic links resolved
  } catch (const io::Error&) {
    *why = "leads outside the asset folder " + root.string() + " (a symbolic link?)";
    return {};
  }
}

// The state tinygltf's callbacks see.
struct Reader {
  fs::path base, root;  // canonical: the glTF's folder, and the folder uris may reach into
  LoadLimits limits;
  Budget budget;
  std::vector<bool> used_images;                   // decoded only when a material uses them
  std::string error;                               // the first refusal, for a clear message
  std::vector<std::string>* files_read = nullptr;  // LoadOptions::files_read
};

std::string expand_path(const std::string& path, void*) { return path; }  // no ~, no variables, no wordexp

// tinygltf joins its base folder with the uri, then tries "." + uri: only the first, confined.
std::string confined(const std::string& joined, Reader& r, std::string* why) {
  const fs::path p(joined);
  if (!p.is_absolute()) {
    *why = "is not beside the glTF (the current folder is not searched)";
    return {};
  }
  const fs::path rel = p.lexically_relative(r.base);
  return resolve_uri(rel.string(), r.base, r.root, why);
}

bool file_exists(const std::string& joined, void* user) {
  Reader& r = *static_cast<Reader*>(user);
  std::string why;
  const std::string file = confined(joined, r, &why);
  struct stat st {};
  if (file.empty() || ::stat(file.c_str(), &st) != 0) return false;
  return true;  // read_whole_file says why a non-regular file is refused
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& joined,
                     void* user) {
  Reader& r = *static_cast<Reader*>(user);
  std::string why;
  const std::string file = confined(joined, r, &why);
  if (!file.empty()) {
    try {
      read_within(file, r.root.string(), r.limits, r.budget, out);  // confined again as it is opened
      if (r.files_read) r.files_read->push_back(file);
      return true;
    } catch (const io::Error& e) { why = e.what(); }
  }
  if (err) *err += why;
  if (r.error.empty()) r.error = why;
  return false;
}

bool write_whole_file(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
  if (err) *err += "the glTF reader writes nothing";
  return false;
}

// Decodes an image a material uses, after its header shows it within the limits; others stay empty.
bool load_image(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                const unsigned char* bytes, int size, void* user) {
  Reader& r = *static_cast<Reader*>(user);
  if (index < 0 || std::size_t(index) >= r.used_images.size() || !r.used_images[std::size_t(index)])
    return true;
  const std::string what = "image " + std::to_string(index);
  auto refuse = [&](const std::string& why) {
    if (err) *err += what + ": " + why;
    if (r.error.empty()) r.error = what + ": " + why;
    return false;
  };
  int w = 0, h = 0, comp = 0;
  if (size <= 0 || !stbi_info_from_memory(bytes, size, &w, &h, &comp) || w <= 0 || h <= 0)
    return refuse("not an image stb_image reads (PNG, JPEG, ...)");
  const std::uint64_t pixels = std::uint64_t(w) * std::uint64_t(h);
  if (pixels > r.limits.max_image_pixels)
    return refuse(std::to_string(w) + " x " + std::to_string(h) +
                  " pixels, more than the load limit max_image_pixels (" +
                  std::to_string(r.limits.max_image_pixels) + ")");
  if (pixels * 4 > r.budget.left)
    return refuse("decoding needs more bytes than the load limit max_total_bytes leaves");
  r.budget.left -= pixels * 4;
  unsigned char* data = stbi_load_from_memory(bytes, size, &w, &h, &comp, 4);
  if (!data) return refuse(std::string("cannot decode: ") + stbi_failure_reason());
  image->width = w;
  image->height = h;
  image->component = 4;
  image->bits = 8;
  image->pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image->image.assign(data, data + std::size_t(w) * std::size_t(h) * 4);
  stbi_image_free(data);
  return true;
}

// The glTF's JSON, checked before tinygltf sees it: uris confined, the node hierarchy a tree
// within the limits, MSFT_lod levels within max_levels. Marks the images materials use.
void check_document(const nlohmann::json& doc, const std::string& path, Reader& r) {
  using nlohmann::json;
  if (!doc.is_object()) throw InputError(path + ": the glTF JSON is not an object");
  auto array = [&](const char* key) -> const json& {
    static const json empty = json::array();
    const auto it = doc.find(key);
    if (it == doc.end()) return empty;
    if (!it->is_array()) throw InputError(path + ": '" + key + "' is not an array");
    return *it;
  };
  auto index = [&](const json& v, std::size_t count, const std::string& what) {
    if (!v.is_number_integer() || v.get<long long>() < 0 || std::uint64_t(v.get<long long>()) >= count)
      throw InputError(path + ": " + what + " is not an index below " + std::to_string(count));
    return std::size_t(v.get<long long>());
  };
  for (const char* key : {"buffers", "images"}) {
    const json& items = array(key);
    for (std::size_t i = 0; i < items.size(); ++i) {
      if (!items[i].is_object() || !items[i].contains("uri")) continue;
      const json& uri = items[i]["uri"];
      const std::string what =
          path + ": " + std::string(key, std::strlen(key) - 1) + " " + std::to_string(i) + " uri";
      if (!uri.is_string()) throw InputError(what + " is not a string");
      const std::string u = uri.get<std::string>();
      if (u.rfind("data:", 0) == 0) continue;
      std::string why;
      if (resolve_uri(u, r.base, r.root, &why).empty()) throw InputError(what + " '" + u + "' " + why);
    }
  }
  // Nodes: a strict tree within max_nodes, max_children, max_node_depth; MSFT_lod within max_levels.
  const json& nodes = array("nodes");
  const LoadLimits& L = r.limits;
  if (nodes.size() > L.max_nodes)
    throw InputError(path + ": " + std::to_string(nodes.size()) +
                     " nodes, more than the load limit max_nodes (" + std::to_string(L.max_nodes) + ")");
  std::vector<std::int64_t> parent(nodes.size(), -1);
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    const std::string where = path + ": node " + std::to_string(n);
    if (!nodes[n].is_object()) throw InputError(where + " is not an object");
    if (const auto c = nodes[n].find("children"); c != nodes[n].end()) {
      if (!c->is_array()) throw InputError(where + ": children is not an array");
      if (c->size() > L.max_children)
        throw InputError(where + ": " + std::to_string(c->size()) +
                         " children, more than the load limit max_children (" +
                         std::to_string(L.max_children) + ")");
      for (const json& v : *c) {
        const std::size_t child = index(v, nodes.size(), "node " + std::to_string(n) + " child");
        if (parent[child] == std::int64_t(n))
          throw InputError(where + " lists child " + std::to_string(child) + " twice (glTF requires a tree)");
        if (parent[child] >= 0)
          throw InputError(path + ": node " + std::to_string(child) + " has two parents, " +
                           std::to_string(parent[child]) + " and " + std::to_string(n) +
                           " (glTF requires a tree)");
        if (child == n) throw InputError(where + " is its own child (a cycle)");
        parent[child] = std::int64_t(n);
      }
    }
    if (const auto e = nodes[n].find("extensions"); e != nodes[n].end() && e->is_object())
      if (const auto lod = e->find("MSFT_lod"); lod != e->end() && lod->is_object())
        if (const auto ids = lod->find("ids"); ids != lod->end()) {
          if (!ids->is_array()) throw InputError(where + ": MSFT_lod ids is not an array");
          if (ids->size() + 1 > L.max_levels)
            throw InputError(where + ": MSFT_lod has " + std::to_string(ids->size() + 1) +
                             " levels, more than the load limit max_levels (" + std::to_string(L.max_levels) +
                             ")");
          for (const json& v : *ids) index(v, nodes.size(), "node " + std::to_string(n) + " MSFT_lod id");
        }
  }
  // Depth and cycles: every node's chain of parents must end at a root within max_node_depth
  // steps (a cycle never ends). depth[] memoises, so this is linear.
  std::vector<std::uint32_t> depth(nodes.size(), 0);  // 0: not known yet; else depth + 1
  std::vector<std::size_t> chain;
  for (std::size_t n = 0; n < nodes.size(); ++n) {
    chain.clear();
    std::size_t at = n;
    while (depth[at] == 0 && parent[at] >= 0) {
      chain.push_back(at);
      if (chain.size() > std::size_t(L.max_node_depth) + 1)
        throw InputError(path + ": node " + std::to_string(n) +
                         " is deeper than the load limit max_node_depth (" +
                         std::to_string(L.max_node_depth) + "), or the hierarchy has a cycle");
      at = std::size_t(parent[at]);
    }
    std::uint32_t d = depth[at] ? depth[at] : (depth[at] = 1);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) depth[*it] = ++d;
    if (d - 1 > L.max_node_depth)
      throw InputError(path + ": node " + std::to_string(n) +
                       " is deeper than the load limit max_node_depth (" + std::to_string(L.max_node_depth) +
                       ")");
  }
  const json& scenes = array("scenes");
  for (std::size_t s = 0; s < scenes.size(); ++s) {
    if (!scenes[s].is_object() || !scenes[s].contains("nodes")) continue;
    const json& roots = scenes[s]["nodes"];
    if (!roots.is_array()) throw InputError(path + ": scene " + std::to_string(s) + " nodes is not an array");
    std::vector<bool> seen(nodes.size(), false);
    for (const json& v : roots) {
      const std::size_t root = index(v, nodes.size(), "scene " + std::to_string(s) + " node");
      if (parent[root] >= 0)
        throw InputError(path + ": scene " + std::to_string(s) + " lists node " + std::to_string(root) +
                         ", which has a parent (" + std::to_string(parent[root]) +
                         "); scene nodes must be roots");
      if (seen[root])
        throw InputError(path + ": scene " + std::to_string(s) + " lists node " + std::to_string(root) +
                         " twice");
      seen[root] = true;
    }
  }
  // The images base-colour textures use: the only ones decoded.
  const json& images = array("images");
  const json& textures = array("textures");
  r.used_images.assign(images.size(), false);
  for (const json& m : array("materials")) {
    if (!m.is_object()) continue;
    const json* t = &m;
    for (const char* key : {"pbrMetallicRoughness", "baseColorTexture", "index"}) {
      if (!t->is_object() || !t->contains(key)) {
        t = nullptr;
        break;
      }
      t = &(*t)[key];
    }
    if (!t || !t->is_number_integer() || t->get<long long>() < 0 ||
        std::uint64_t(t->get<long long>()) >= textures.size())
      continue;
    const json& tex = textures[std::size_t(t->get<long long>())];
    if (!tex.is_object() || !tex.contains("source") || !tex["source"].is_number_integer()) continue;
    const long long source = tex["source"].get<long long>();
    if (source >= 0 && std::uint64_t(source) < images.size()) r.used_images[std::size_t(source)] = true;
  }
}

std::uint32_t le32(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
         std::uint32_t(p[3]) << 24;
}

Scene load_gltf(const std::string& path, const LoadOptions& options) {
  Reader r;
  r.limits = options.limits;
  r.files_read = options.files_read;
  r.budget.left = options.limits.max_total_bytes;
  r.budget.path = path;
  std::error_code ec;
  r.base = fs::weakly_canonical(fs::absolute(fs::path(path), ec).parent_path(), ec);
  if (ec) throw InputError(path + ": cannot resolve its folder: " + ec.message());
  r.root = r.base;
  if (!options.asset_root.empty()) {
    r.root = fs::weakly_canonical(fs::absolute(options.asset_root, ec), ec);
    if (ec || !fs::is_directory(r.root))
      throw InputError(options.asset_root + ": the asset root is not a folder");
    const fs::path rel = r.base.lexically_relative(r.root);
    if (rel.empty() || *rel.begin() == "..")
      throw InputError(path + ": is not inside the asset root " + r.root.string());
  }
  std::vector<unsigned char> bytes;
  read_within(path, "", r.limits, r.budget, &bytes);
  // The JSON: the whole .gltf, or a .glb's first chunk (framing checked here; tinygltf rechecks).
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const char* json_text = reinterpret_cast<const char*>(bytes.data());
  std::size_t json_size = bytes.size();
  if (glb) {
    if (bytes.size() < 20) throw InputError(path + ": GLB shorter than its 20-byte header");
    const std::uint32_t length = le32(&bytes[8]), chunk = le32(&bytes[12]);
    if (le32(&bytes[4]) != 2)
      throw InputError(path + ": GLB version " + std::to_string(le32(&bytes[4])) + ", not 2");
    if (length > bytes.size() || std::uint64_t(chunk) + 20 > length || le32(&bytes[16]) != 0x4E4F534Au)
      throw InputError(path + ": malformed GLB header (lengths past the file, or no JSON chunk first)");
    json_text += 20;
    json_size = chunk;
  }
  check_json_depth(json_text, json_size, r.limits.max_json_depth, path);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(json_text, json_text + json_size);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not a readable glTF 2.0 file: invalid JSON: " + e.what());
  }
  check_document(doc, path, r);
  doc = nlohmann::json();

  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks(
      tinygltf::FsCallbacks{file_exists, expand_path, read_whole_file, write_whole_file, &r});
  loader.SetImageLoader(load_image, &r);
  tinygltf::Model model;
  std::string err, warn;
  const std::string base = r.base.string();
  const bool ok =
      glb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), base)
          : loader.LoadASCIIFromString(&model, &err, &warn, json_text, unsigned(json_size), base);
  if (!r.error.empty()) throw InputError(path + ": " + r.error);
  if (!ok)
    throw InputError(path + ": not a readable glTF 2.0 file: " + (err.empty() ? "unknown error" : err));
  bytes = {};  // tinygltf checked each buffer's byteLength; accessor_span checks against the bytes held
  return convert(model, path, r.limits, r.budget);
}

}  // namespace

Scene load_scene(const std::string& path, const LoadOptions& options) {
  const InputFormat* format = input_format(path);
  if (!format)
    throw InputError(path + ": lodgen reads " + input_format_names() + " files, not '" +
                     io::lower_extension(path) + "'");
  if (format->reader == FormatReader::OpenMesh) {
    io::ReadLimits bound;  // the reader opens the file itself: its size is checked here first
    bound.max_bytes = options.limits.max_file_bytes;
    bound.max_bytes_name = "the load limit max_file_bytes";
    io::check_input(path, bound);
    Scene s;
    s.meshes.push_back(options.isolate_mesh_reader ? load_mesh_isolated(path) : load_mesh(path));
    s.mesh_names.push_back(std::filesystem::path(path).stem().string());
    Node n;
    n.name = s.mesh_names[0];
    n.mesh = 0;
    s.nodes.push_back(n);
    s.roots.push_back(0);
    return s;
  }
  return load_gltf(path, options);
}

std::vector<PlacedNode> world_matrices(const Scene& scene, const std::function<bool(int)>& skip) {
  std::vector<PlacedNode> out;
  std::vector<bool> reached(scene.nodes.size(), false);
  std::vector<PlacedNode> stack;  // (node, its parent's world matrix)
  const std::array<double, 16> identity{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  auto push = [&](int n, const std::array<double, 16>& parent) {
    if (n < 0 || std::size_t(n) >= scene.nodes.size())
      throw InputError("node " + std::to_string(n) + " does not exist");
    if (skip && skip(n)) return;
    if (reached[std::size_t(n)])
      throw InputError("node " + std::to_string(n) +
                       " is reached twice: the node hierarchy has a cycle or a node with two parents");
    reached[std::size_t(n)] = true;
    stack.push_back({n, parent});
  };
  for (auto r = scene.roots.rbegin(); r != scene.roots.rend(); ++r) push(*r, identity);
  while (!stack.empty()) {
    const PlacedNode top = stack.back();
    stack.pop_back();
    const Node& node = scene.nodes[std::size_t(top.node)];
    PlacedNode placed{top.node, {}};
    for (int c = 0; c < 4; ++c)  // column-major parent * local
      for (int r = 0; r < 4; ++r)
        for (int k = 0; k < 4; ++k)
          placed.world[std::size_t(c * 4 + r)] +=
              top.world[std::size_t(k * 4 + r)] * node.matrix[std::size_t(c * 4 + k)];
    out.push_back(placed);
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) push(*c, placed.world);
  }
  return out;
}

std::vector<double> screen_coverage(const std::vector<double>& error, double height) {
  std::vector<double> out(error.size(), 0.0);
  for (std::size_t k = 0; k + 1 < error.size(); ++k) {
    const double e = error[k + 1];  // level k is drawn down to where level k + 1's error covers 1 px
    const double c = e > 0 ? 1.0 / (e * height) : 1.0;
    out[k] = std::clamp(c, 0.0, k ? out[k - 1] : 1.0);
  }
  return out;
}

std::vector<double> lod_geometric_errors(const Node& top, std::size_t levels) {
  std::vector<double> out(levels, 0.0);
  if (top.geometric_error.size() == levels) return top.geometric_error;
  const double height = GltfWriteOptions{}.reference_height;
  for (std::size_t k = 1; k < levels; ++k) {  // coverage[k - 1] = 1 / (e_k x height)
    const double c = k - 1 < top.screen_coverage.size() ? top.screen_coverage[k - 1] : 0;
    out[k] = c > 0 ? 1.0 / (c * height) : 0.0;
  }
  return out;
}

Chain chain_of_node(const Scene& scene, const Node& top) {
  Chain c;
  std::vector<Mesh> meshes = {scene.meshes[std::size_t(top.mesh)]};
  for (int id : top.lods)
    if (scene.nodes[std::size_t(id)].mesh >= 0)
      meshes.push_back(scene.meshes[std::size_t(scene.nodes[std::size_t(id)].mesh)]);
  const std::vector<double> errors = lod_geometric_errors(top, meshes.size());
  for (std::size_t k = 0; k < meshes.size(); ++k) {
    const std::size_t triangles = meshes[k].triangle_count();
    c.levels.push_back({std::move(meshes[k]), triangles, errors[k], 0.0});
  }
  c.diameter = diameter(c.levels[0].mesh);
  return c;
}

void write_lod_gltf(const std::string& path, const std::vector<LodObject>& objects,
                    const std::vector<Material>& materials, const GltfWriteOptions& options,
                    const std::vector<LodInstance>& instances) {
  std::string bytes;
  try {
    bytes = encode_lod_gltf(objects, materials, options, instances);
  } catch (const std::runtime_error& e) { throw std::runtime_error(path + ": " + e.what()); }
  io::write_file_atomically(path, bytes);
}

std::string encode_lod_gltf(const std::vector<LodObject>& objects, const std::vector<Material>& materials,
                            const GltfWriteOptions& options, const std::vector<LodInstance>& instances) {
  if (!(options.reference_height >= 1) || !std::isfinite(options.reference_height))
    throw std::runtime_error("reference height " + std::to_string(options.reference_height) +
                             " is not a finite height >= 1 px");
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "acuity lodgen";
  model.buffers.emplace_back();
  BufferWriter w{model, model.buffers[0].data};
  for (const Material& src : materials) {
    tinygltf::Material m;
    m.name = src.name;
    m.pbrMetallicRoughness.baseColorFactor = {src.base_color[0], src.base_color[1], src.base_color[2],
                                              src.base_color[3]};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (!src.pixels.empty()) {
      std::vector<unsigned char> png;
      if (!stbi_write_png_to_func(append_png, &png, src.width, src.height, 4, src.pixels.data(),
                                  src.width * 4))
        throw std::runtime_error("cannot encode the texture of material '" + src.name + "'");
      tinygltf::Image img;
      img.mimeType = "image/png";
      img.bufferView = w.view(png.data(), png.size(), 0);
      model.images.push_back(img);
      tinygltf::Texture tex;
      tex.source = int(model.images.size() - 1);
      model.textures.push_back(tex);
      m.pbrMetallicRoughness.baseColorTexture.index = int(model.textures.size() - 1);
    }
    model.materials.push_back(m);
  }
  // Meshes once per object and level; nodes once per instance (instances share the meshes).
  std::vector<std::vector<int>> mesh_ids(objects.size());
  bool any_clusters = false;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const LodObject& o = objects[i];
    for (std::size_t k = 0; k < o.chain.levels.size(); ++k) {
      const Mesh& mesh = o.chain.levels[k].mesh;
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.attributes["POSITION"] = w.accessor(mesh.positions, 3, true);
      if (!mesh.normals.empty()) prim.attributes["NORMAL"] = w.accessor(mesh.normals, 3, false);
      if (!mesh.texcoords.empty()) prim.attributes["TEXCOORD_0"] = w.accessor(mesh.texcoords, 2, false);
      if (k == 0 && !o.clusters.empty()) {
        if (const std::string fault = check_cluster_hierarchy(o.clusters, mesh.vertex_count());
            !fault.empty())
          throw std::runtime_error("object '" + o.name + "': its cluster hierarchy is invalid: " + fault);
        if (3 * o.clusters.finest_triangles() != mesh.indices.size())
          throw std::runtime_error("object '" + o.name +
                                   "': its cluster hierarchy's finest clusters are not level 0");
        write_clusters(w, o.clusters, prim);
        any_clusters = true;
      } else {
        prim.indices = w.indices(mesh.indices);
      }
      if (o.material >= 0 && o.material < int(materials.size())) prim.material = o.material;
      tinygltf::Mesh gm;
      gm.name = o.name + (k ? "_LOD" + std::to_string(k) : std::string());
      gm.primitives.push_back(prim);
      model.meshes.push_back(gm);
      mesh_ids[i].push_back(int(model.meshes.size() - 1));
    }
  }
  std::vector<LodInstance> placed = instances;
  if (placed.empty())
    for (std::size_t i = 0; i < objects.size(); ++i)
      placed.push_back({int(i), objects[i].name, objects[i].matrix});
  tinygltf::Scene scene;
  for (const LodInstance& in : placed) {
    if (in.object < 0 || in.object >= int(objects.size()))
      throw std::runtime_error("instance '" + in.name + "' names object " + std::to_string(in.object) +
                               ", which does not exist");
    const LodObject& o = objects[std::size_t(in.object)];
    std::vector<double> geometric_error;
    for (const Level& l : o.chain.levels) geometric_error.push_back(l.hausdorff);
    const std::vector<double> coverage = screen_coverage(geometric_error, options.reference_height);
    std::vector<int> node_ids;
    for (std::size_t k = 0; k < o.chain.levels.size(); ++k) {
      tinygltf::Node node;
      node.name = in.name + (k ? "_LOD" + std::to_string(k) : std::string());
      node.mesh = mesh_ids[std::size_t(in.object)][k];
      if (!identity(in.matrix)) node.matrix.assign(in.matrix.begin(), in.matrix.end());
      model.nodes.push_back(node);
      node_ids.push_back(int(model.nodes.size() - 1));
    }
    tinygltf::Node& top = model.nodes[std::size_t(node_ids[0])];
    if (node_ids.size() > 1) {
      tinygltf::Value::Array ids, cov, err;
      for (std::size_t k = 1; k < node_ids.size(); ++k) ids.emplace_back(node_ids[k]);
      for (double c : coverage) cov.emplace_back(c);
      for (double e : geometric_error) err.emplace_back(e);
      tinygltf::Value::Object lod;
      lod["ids"] = tinygltf::Value(ids);
      top.extensions["MSFT_lod"] = tinygltf::Value(lod);
      tinygltf::Value::Object extras;
      extras["MSFT_screencoverage"] = tinygltf::Value(cov);
      extras["acuity_geometric_error"] = tinygltf::Value(err);
      tinygltf::Value::Array normal;
      for (const Level& l : o.chain.levels) normal.emplace_back(l.normal_deviation);
      extras["acuity_normal_deviation"] = tinygltf::Value(normal);
      top.extras = tinygltf::Value(extras);
    }
    scene.nodes.push_back(node_ids[0]);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.extensionsUsed.push_back("MSFT_lod");
  if (any_clusters) model.extensionsUsed.push_back(kClusterExtension);  // optional: not required
  model.buffers[0].uri.clear();

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  // .glb, or .gltf with the buffer embedded as a data URI: one file holds everything.
  if (!writer.WriteGltfSceneToStream(&model, stream, !options.binary, options.binary))
    throw std::runtime_error("cannot encode glTF");
  return stream.str();
}

}  // namespace acuity::lodgen
