// glTF input (tinygltf) with every accessor bounds-checked, and LOD output with MSFT_lod.
#include "acuity/lodgen/gltf.hpp"

#include "path.hpp"

#include <stb_image_write.h>
#include <tiny_gltf.h>

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

[[noreturn]] void fail(const std::string& where, const std::string& what) { throw InputError(where + ": " + what); }

// Reads accessor `index` as `components` floats per element (FLOAT, or normalised integers).
std::vector<float> read_floats(const Model& m, int index, int components, const std::string& where) {
  if (index < 0 || index >= int(m.accessors.size())) fail(where, "accessor " + std::to_string(index) + " does not exist");
  const Accessor& a = m.accessors[index];
  const std::string at = where + ", accessor " + std::to_string(index);
  if (a.sparse.isSparse) fail(at, "sparse accessors are not supported");
  if (tinygltf::GetNumComponentsInType(a.type) != components)
    fail(at, "expected " + std::to_string(components) + " components per element");
  if (a.bufferView < 0 || a.bufferView >= int(m.bufferViews.size())) fail(at, "no valid bufferView");
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) fail(at, "bufferView names no valid buffer");
  const std::vector<unsigned char>& buf = m.buffers[v.buffer].data;
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (csize <= 0) fail(at, "unknown component type");
  const std::size_t element = std::size_t(csize) * components;
  const std::size_t stride = v.byteStride ? v.byteStride : element;
  if (a.count > 0 && (stride < element || a.count > (std::numeric_limits<std::size_t>::max() - element) / stride))
    fail(at, "absurd count or stride");
  const std::size_t need = a.count == 0 ? 0 : a.byteOffset + (a.count - 1) * stride + element;
  if (need > v.byteLength || v.byteOffset > buf.size() || v.byteLength > buf.size() - v.byteOffset)
    fail(at, "reads past the end of its buffer");
  const unsigned char* base = buf.data() + v.byteOffset + a.byteOffset;
  std::vector<float> out(a.count * components);
  for (std::size_t i = 0; i < a.count; ++i)
    for (int c = 0; c < components; ++c) {
      const unsigned char* p = base + i * stride + std::size_t(c) * csize;
      float x;
      switch (a.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT: std::memcpy(&x, p, 4); break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: x = float(*p) / 255.0f; break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t s; std::memcpy(&s, p, 2); x = float(s) / 65535.0f; break; }
        default: fail(at, "component type " + std::to_string(a.componentType) + " is not a float or normalised type");
      }
      if (!std::isfinite(x)) fail(at, "element " + std::to_string(i) + " is not finite");
      out[i * components + c] = x;
    }
  return out;
}

std::vector<std::uint32_t> read_indices(const Model& m, int index, std::size_t vertex_count, const std::string& where) {
  if (index < 0) {  // non-indexed: 0, 1, 2, ...
    std::vector<std::uint32_t> out(vertex_count);
    for (std::size_t i = 0; i < vertex_count; ++i) out[i] = std::uint32_t(i);
    return out;
  }
  if (index >= int(m.accessors.size())) fail(where, "index accessor " + std::to_string(index) + " does not exist");
  const Accessor& a = m.accessors[index];
  const std::string at = where + ", index accessor " + std::to_string(index);
  if (a.type != TINYGLTF_TYPE_SCALAR || a.bufferView < 0 || a.bufferView >= int(m.bufferViews.size()))
    fail(at, "must be scalar with a valid bufferView");
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) fail(at, "bufferView names no valid buffer");
  const std::vector<unsigned char>& buf = m.buffers[v.buffer].data;
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<std::uint32_t>(a.componentType));
  if (csize != 1 && csize != 2 && csize != 4) fail(at, "indices must be unsigned byte, short or int");
  const std::size_t stride = v.byteStride ? v.byteStride : std::size_t(csize);
  if (a.count > 0 && a.count > (std::numeric_limits<std::size_t>::max() - csize) / stride) fail(at, "absurd count");
  const std::size_t need = a.count == 0 ? 0 : a.byteOffset + (a.count - 1) * stride + csize;
  if (need > v.byteLength || v.byteOffset > buf.size() || v.byteLength > buf.size() - v.byteOffset)
    fail(at, "reads past the end of its buffer");
  const unsigned char* base = buf.data() + v.byteOffset + a.byteOffset;
  std::vector<std::uint32_t> out(a.count);
  for (std::size_t i = 0; i < a.count; ++i) {
    std::uint32_t x = 0;
    std::memcpy(&x, base + i * stride, std::size_t(csize));  // little-endian
    if (x >= vertex_count) fail(at, "index " + std::to_string(x) + " at element " + std::to_string(i) + " is out of range");
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
  const double rot[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
                         2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                         2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};  // columns
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k) m[c * 4 + k] = rot[c * 3 + k] * s[c];
  for (int k = 0; k < 3; ++k) m[12 + k] = t[k];
  return m;
}

Scene convert(const Model& model, const std::string& path) {
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
        if (img.width > 0 && img.height > 0 && img.bits == 8 &&
            img.image.size() == std::size_t(img.width) * img.height * img.component) {
          mat.width = img.width;
          mat.height = img.height;
          mat.pixels.resize(std::size_t(img.width) * img.height * 4, 255);
          for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i)
            for (int c = 0; c < std::min(img.component, 4); ++c) mat.pixels[i * 4 + c] = img.image[i * img.component + c];
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
      const std::string where = path + ": mesh " + std::to_string(mi) + " ('" + src.name + "') primitive " + std::to_string(pi);
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) fail(where, "only triangle primitives are supported");
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail(where, "has no POSITION");
      Mesh m;
      m.positions = read_floats(model, pos->second, 3, where);
      if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) m.normals = read_floats(model, it->second, 3, where);
      if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) m.texcoords = read_floats(model, it->second, 2, where);
      if ((!m.normals.empty() && m.normals.size() != m.positions.size()) ||
          (!m.texcoords.empty() && m.texcoords.size() / 2 != m.positions.size() / 3))
        fail(where, "attributes differ in length from POSITION");
      m.indices = read_indices(model, prim.indices, m.vertex_count(), where);
      if (m.indices.size() % 3) fail(where, "index count " + std::to_string(m.indices.size()) + " is not a multiple of 3");
      m.material = prim.material >= 0 && prim.material < int(scene.materials.size()) ? prim.material : -1;
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
      if (c < 0 || c >= int(model.nodes.size())) fail(path + ": node " + std::to_string(ni), "child " + std::to_string(c) + " does not exist");
      n.children.push_back(c);
    }
    if (src.mesh >= 0) {
      if (src.mesh >= int(model.meshes.size())) fail(path + ": node " + std::to_string(ni), "mesh " + std::to_string(src.mesh) + " does not exist");
      if (mesh_count[src.mesh] > 0) n.mesh = mesh_first[src.mesh];
    }
    if (auto it = src.extensions.find("MSFT_lod"); it != src.extensions.end() && it->second.Has("ids")) {
      const tinygltf::Value& ids = it->second.Get("ids");
      for (std::size_t i = 0; i < ids.ArrayLen(); ++i) n.lods.push_back(ids.Get(int(i)).GetNumberAsInt());
    }
    if (src.extras.Has("MSFT_screencoverage")) {
      const tinygltf::Value& c = src.extras.Get("MSFT_screencoverage");
      for (std::size_t i = 0; i < c.ArrayLen(); ++i) n.screen_coverage.push_back(c.Get(int(i)).GetNumberAsDouble());
    }
    if (src.extras.Has("acuity_geometric_error")) {
      const tinygltf::Value& e = src.extras.Get("acuity_geometric_error");
      for (std::size_t i = 0; i < e.ArrayLen(); ++i) {
        const double x = e.Get(int(i)).GetNumberAsDouble();
        if (!(x >= 0) || !std::isfinite(x))
          fail(path + ": node " + std::to_string(ni), "acuity_geometric_error[" + std::to_string(i) + "] is not a finite error >= 0");
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
      if (r < 0 || r >= int(model.nodes.size())) fail(path, "scene root " + std::to_string(r) + " does not exist");
      scene.roots.push_back(r);
    }
  } else {
    for (std::size_t i = 0; i < model.nodes.size(); ++i) scene.roots.push_back(int(i));
  }
  for (const Node& n : scene.nodes)
    for (int l : n.lods)
      if (l < 0 || l >= int(scene.nodes.size())) fail(path, "MSFT_lod names node " + std::to_string(l) + ", which does not exist");
  return scene;
}

using detail::lower_extension;

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
    tinygltf::Accessor a;
    a.bufferView = view(values.data(), values.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
    a.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    a.count = values.size();
    a.type = TINYGLTF_TYPE_SCALAR;
    model.accessors.push_back(a);
    return int(model.accessors.size() - 1);
  }
};

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

Scene load_scene(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".gltf" && ext != ".glb") {
    Scene s;
    s.meshes.push_back(load_mesh(path));
    s.mesh_names.push_back(std::filesystem::path(path).stem().string());
    Node n;
    n.name = s.mesh_names[0];
    n.mesh = 0;
    s.nodes.push_back(n);
    s.roots.push_back(0);
    return s;
  }
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err, warn;
  const bool ok = ext == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!ok) throw InputError(path + ": not a readable glTF 2.0 file: " + (err.empty() ? "unknown error" : err));
  return convert(model, path);
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

void write_lod_gltf(const std::string& path, const std::vector<LodObject>& objects, const std::vector<Material>& materials,
                    const GltfWriteOptions& options, const std::vector<LodInstance>& instances) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "acuity lodgen";
  model.buffers.emplace_back();
  BufferWriter w{model, model.buffers[0].data};
  for (const Material& src : materials) {
    tinygltf::Material m;
    m.name = src.name;
    m.pbrMetallicRoughness.baseColorFactor = {src.base_color[0], src.base_color[1], src.base_color[2], src.base_color[3]};
    m.pbrMetallicRoughness.metallicFactor = 0.0;
    m.pbrMetallicRoughness.roughnessFactor = 1.0;
    if (!src.pixels.empty()) {
      std::vector<unsigned char> png;
      if (!stbi_write_png_to_func(append_png, &png, src.width, src.height, 4, src.pixels.data(), src.width * 4))
        throw std::runtime_error(path + ": cannot encode the texture of material '" + src.name + "'");
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
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const LodObject& o = objects[i];
    for (std::size_t k = 0; k < o.levels.size(); ++k) {
      const Mesh& mesh = o.levels[k];
      tinygltf::Primitive prim;
      prim.mode = TINYGLTF_MODE_TRIANGLES;
      prim.attributes["POSITION"] = w.accessor(mesh.positions, 3, true);
      if (!mesh.normals.empty()) prim.attributes["NORMAL"] = w.accessor(mesh.normals, 3, false);
      if (!mesh.texcoords.empty()) prim.attributes["TEXCOORD_0"] = w.accessor(mesh.texcoords, 2, false);
      prim.indices = w.indices(mesh.indices);
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
    for (std::size_t i = 0; i < objects.size(); ++i) placed.push_back({int(i), objects[i].name, objects[i].matrix});
  tinygltf::Scene scene;
  for (const LodInstance& in : placed) {
    if (in.object < 0 || in.object >= int(objects.size()))
      throw std::runtime_error(path + ": instance '" + in.name + "' names object " + std::to_string(in.object) + ", which does not exist");
    const LodObject& o = objects[std::size_t(in.object)];
    const std::vector<double> coverage = screen_coverage(o.geometric_error, options.reference_height);
    std::vector<int> node_ids;
    for (std::size_t k = 0; k < o.levels.size(); ++k) {
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
      for (double e : o.geometric_error) err.emplace_back(e);
      tinygltf::Value::Object lod;
      lod["ids"] = tinygltf::Value(ids);
      top.extensions["MSFT_lod"] = tinygltf::Value(lod);
      tinygltf::Value::Object extras;
      extras["MSFT_screencoverage"] = tinygltf::Value(cov);
      extras["acuity_geometric_error"] = tinygltf::Value(err);
      top.extras = tinygltf::Value(extras);
    }
    scene.nodes.push_back(node_ids[0]);
  }
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  model.extensionsUsed.push_back("MSFT_lod");
  model.buffers[0].uri.clear();

  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  // .glb, or .gltf with the buffer embedded as a data URI: one file holds everything.
  if (!writer.WriteGltfSceneToStream(&model, stream, !options.binary, options.binary))
    throw std::runtime_error(path + ": cannot encode glTF");
  const std::string bytes = stream.str();
  std::string error;
  if (!write_file_atomically(path, bytes.data(), bytes.size(), &error)) throw std::runtime_error(error);
}

}  // namespace acuity::lodgen
