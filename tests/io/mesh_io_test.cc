// Reading meshes: an OBJ with its materials' colours, binary and ASCII STL, millimetres, and the
// one-line errors for a file that is not a mesh Saccade reads.
#include "io/formats/mesh_io.h"

#include "io/formats/cloud_io.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <cstring>
#include <filesystem>
#include <fstream>

namespace saccade {
namespace {

// A folder of this test process's own, removed at the end.
struct Folder {
  std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("saccade_mesh_test_" + std::to_string(getpid()));
  Folder() { std::filesystem::create_directories(dir); }
  ~Folder() { std::filesystem::remove_all(dir); }
  std::string Path(const std::string& name) const { return (dir / name).string(); }
};

void Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

TEST(LoadMesh, ReadsAnObjWithItsMaterialsColoursAndSplitsItsQuads) {
  const Folder box;
  Write(box.Path("m.mtl"), "newmtl red\nKd 1.0 0.0 0.0\nnewmtl blue\nKd 0 0 1\n");
  Write(box.Path("m.obj"),
        "# a square and a triangle\nmtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "vn 0 0 1\nvt 0 0\nusemtl red\nf 1/1/1 2/1/1 3/1/1 4/1/1\nusemtl blue\nf -4 -3 -1\n");
  std::string error;
  const auto mesh = LoadMesh(box.Path("m.obj"), 0.001f, &error);
  ASSERT_TRUE(mesh) << error;
  ASSERT_EQ(mesh->vertices.size(), 4u);
  EXPECT_FLOAT_EQ(mesh->vertices[2].x(), 0.001f);  // millimetres made metres
  ASSERT_EQ(mesh->triangles.size(), 3u);
  EXPECT_EQ(mesh->triangles[2], (std::array<int, 3>{0, 1, 3}));  // negative indices count back
  ASSERT_EQ(mesh->face_colours.size(), 3u);
  EXPECT_EQ(mesh->face_colours[0], (std::array<std::uint8_t, 3>{255, 0, 0}));
  EXPECT_EQ(mesh->face_colours[2], (std::array<std::uint8_t, 3>{0, 0, 255}));
}

TEST(LoadMesh, ReadsBinaryAndAsciiStl) {
  const Folder box;
  std::string binary(80, ' ');
  const std::uint32_t count = 1;
  binary.append(reinterpret_cast<const char*>(&count), 4);
  const float triangle[12] = {0, 0, 1, 0, 0, 0, 2, 0, 0, 0, 3, 0};  // normal, then 3 corners
  binary.append(reinterpret_cast<const char*>(triangle), sizeof triangle);
  binary.append(2, '\0');
  Write(box.Path("b.stl"), binary);
  Write(box.Path("a.STL"),
        "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
        "endloop\nendfacet\nendsolid t\n");
  std::string error;
  const auto b = LoadMesh(box.Path("b.stl"), 1, &error);
  ASSERT_TRUE(b) << error;
  ASSERT_EQ(b->triangles.size(), 1u);
  EXPECT_FLOAT_EQ(b->vertices[1].x(), 2.0f);
  EXPECT_FLOAT_EQ(b->vertices[2].y(), 3.0f);
  const auto a = LoadMesh(box.Path("a.STL"), 1, &error);
  ASSERT_TRUE(a) << error;
  EXPECT_EQ(a->triangles.size(), 1u);
}

TEST(LoadMesh, SaysInOneLineWhatIsWrongAndWhere) {
  const Folder box;
  Write(box.Path("bad.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  Write(box.Path("short.obj"), "v 0 0\n");
  Write(box.Path("x.pcd"), "VERSION 0.7\n");
  Write(box.Path("x.stl"), "not an stl");
  std::string error;
  EXPECT_FALSE(LoadMesh(box.Path("bad.obj"), 1, &error));
  EXPECT_EQ(error, box.Path("bad.obj") + ": face 1 names vertex 7 of 2");
  EXPECT_FALSE(LoadMesh(box.Path("short.obj"), 1, &error));
  EXPECT_EQ(error, box.Path("short.obj") + ":1: a vertex needs three numbers");
  EXPECT_FALSE(LoadMesh(box.Path("x.pcd"), 1, &error));
  EXPECT_EQ(error, box.Path("x.pcd") + ": not a mesh Saccade reads (.obj, .ply or .stl)");
  EXPECT_FALSE(LoadMesh(box.Path("x.stl"), 1, &error));
  EXPECT_NE(error.find("not an STL file"), std::string::npos) << error;
  EXPECT_FALSE(LoadMesh(box.Path("none.obj"), 1, &error));
  EXPECT_EQ(error, box.Path("none.obj") + ": no such file");
}

TEST(LoadCloud, GivenAMeshSaysHowToMakeAModelOfIt) {
  const Folder box;
  Write(box.Path("part.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  std::string error;
  EXPECT_FALSE(LoadCloud(box.Path("part.obj"), &error));
  EXPECT_NE(error.find("saccade model --mesh part.obj --out MODEL.pcd"), std::string::npos)
      << error;
}

}  // namespace
}  // namespace saccade
