// Every offline dependency found, linked and doing one checkable thing: the build's wiring test.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <fftw3.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_reduce.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "acuity/file.hpp"
#include "acuity/lodgen/mesh.hpp"
#include "acuity/lodgen/versions.hpp"
#include "acuity/spectra/versions.hpp"

namespace fs = std::filesystem;

TEST(Dependencies, OpenMeshReadsOff) {
  const fs::path path = fs::temp_directory_path() / "acuity_dep_tetra.off";
  std::ofstream(path) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  const acuity::lodgen::Mesh mesh = acuity::lodgen::load_mesh(path.string());
  EXPECT_EQ(mesh.vertex_count(), 4u);
  EXPECT_EQ(mesh.triangle_count(), 4u);
  fs::remove(path);
  EXPECT_THROW(acuity::lodgen::load_mesh(path.string()),
               acuity::io::Error);  // missing: the file seam says so
}

TEST(Dependencies, CgalMeasuresAUnitCube) {
  using K = CGAL::Simple_cartesian<double>;
  CGAL::Surface_mesh<K::Point_3> m;
  std::vector<CGAL::Surface_mesh<K::Point_3>::Vertex_index> v;
  for (int i = 0; i < 8; ++i) v.push_back(m.add_vertex(K::Point_3(i & 1, (i >> 1) & 1, (i >> 2) & 1)));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.add_face(v[q[0]], v[q[1]], v[q[2]]);
    m.add_face(v[q[0]], v[q[2]], v[q[3]]);
  }
  EXPECT_NEAR(CGAL::Polygon_mesh_processing::area(m), 6.0, 1e-12);
  EXPECT_NEAR(CGAL::Polygon_mesh_processing::volume(m), 1.0, 1e-12);
}

TEST(Dependencies, OpenSubdivRefinesACube) {
  using namespace OpenSubdiv;
  const int verts_per_face[6] = {4, 4, 4, 4, 4, 4};
  const int indices[24] = {0, 2, 3, 1, 4, 5, 7, 6, 0, 1, 5, 4, 2, 6, 7, 3, 0, 4, 6, 2, 1, 3, 7, 5};
  Far::TopologyDescriptor desc;
  desc.numVertices = 8;
  desc.numFaces = 6;
  desc.numVertsPerFace = verts_per_face;
  desc.vertIndicesPerFace = indices;
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  Far::TopologyRefiner* refiner =
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, Sdc::Options()));
  ASSERT_NE(refiner, nullptr);
  refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(2));
  EXPECT_EQ(refiner->GetLevel(1).GetNumFaces(), 24);  // each quad splits in four
  EXPECT_EQ(refiner->GetLevel(2).GetNumFaces(), 96);
  EXPECT_EQ(refiner->GetLevel(1).GetNumVertices(), 26);  // 8 + 12 edge + 6 face points
  delete refiner;
}

TEST(Dependencies, TinyGltfRoundTrip) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "acuity test";
  model.nodes.emplace_back().name = "root";
  model.scenes.emplace_back().nodes = {0};
  model.defaultScene = 0;
  const fs::path path = fs::temp_directory_path() / "acuity_dep.gltf";
  tinygltf::TinyGLTF io;
  ASSERT_TRUE(io.WriteGltfSceneToFile(&model, path.string(), false, false, true, false));
  tinygltf::Model back;
  std::string err, warn;
  ASSERT_TRUE(io.LoadASCIIFromFile(&back, &err, &warn, path.string())) << err;
  ASSERT_EQ(back.nodes.size(), 1u);
  EXPECT_EQ(back.nodes[0].name, "root");
  fs::remove(path);
}

TEST(Dependencies, FftwFindsACosine) {
  const int n = 64;
  std::vector<double> in(n);
  std::vector<fftw_complex> out(n / 2 + 1);
  for (int i = 0; i < n; ++i) in[i] = std::cos(2 * M_PI * 5 * i / n);
  fftw_plan plan = fftw_plan_dft_r2c_1d(n, in.data(), out.data(), FFTW_ESTIMATE);
  fftw_execute(plan);
  fftw_destroy_plan(plan);
  for (int k = 0; k <= n / 2; ++k)
    EXPECT_NEAR(std::hypot(out[k][0], out[k][1]), k == 5 ? n / 2.0 : 0.0, 1e-9) << k;
}

TEST(Dependencies, TbbReduces) {
  const long sum = oneapi::tbb::parallel_reduce(
      oneapi::tbb::blocked_range<long>(1, 100001), 0L,
      [](const oneapi::tbb::blocked_range<long>& r, long acc) {
        for (long i = r.begin(); i != r.end(); ++i) acc += i;
        return acc;
      },
      [](long a, long b) { return a + b; });
  EXPECT_EQ(sum, 100000L * 100001L / 2);
}

TEST(Dependencies, VersionsNameEveryLibrary) {
  const std::string l = acuity::lodgen::library_versions(), s = acuity::spectra::library_versions();
  for (const char* name : {"OpenMesh", "CGAL", "OpenSubdiv"}) EXPECT_NE(l.find(name), std::string::npos) << l;
  for (const char* name : {"FFTW", "oneTBB"}) EXPECT_NE(s.find(name), std::string::npos) << s;
}
