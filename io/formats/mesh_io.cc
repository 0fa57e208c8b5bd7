#include "io/formats/mesh_io.h"

#include "core/fail.h"
#include "io/formats/cloud_io.h"

#include <pcl/PolygonMesh.h>
#include <pcl/console/print.h>
#include <pcl/conversions.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace saccade {
namespace {

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

std::uint8_t Channel(float v) { return std::uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)); }

// Diffuse colours (Kd) by material name; a missing or unreadable MTL gives none.
std::map<std::string, std::array<std::uint8_t, 3>> ReadMtl(const std::filesystem::path& path) {
  std::map<std::string, std::array<std::uint8_t, 3>> out;
  std::ifstream in(path);
  std::string line, current;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "newmtl") {
      s >> current;
    } else if (tag == "Kd" && !current.empty()) {
      float r, g, b;
      if (s >> r >> g >> b) out[current] = {Channel(r), Channel(g), Channel(b)};
    }
  }
  return out;
}

std::optional<Mesh> ReadObj(const std::string& path, std::string* error) {
  std::ifstream in(path);
  if (!in) return Fail(error, path + ": cannot open: " + std::strerror(errno)), std::nullopt;
  Mesh mesh;
  std::map<std::string, std::array<std::uint8_t, 3>> materials;
  std::optional<std::array<std::uint8_t, 3>> colour;
  bool any_colour = false;
  std::vector<std::optional<std::array<std::uint8_t, 3>>> colours;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    const auto bad = [&](const std::string& what) {
      Fail(error, path + ":" + std::to_string(number) + ": " + what);
      return std::nullopt;
    };
    if (tag == "v") {
      float x, y, z;
      if (!(s >> x >> y >> z)) return bad("a vertex needs three numbers");
      mesh.vertices.emplace_back(x, y, z);
    } else if (tag == "f") {
      std::vector<int> face;
      std::string corner;
      while (s >> corner) {
        // v, v/vt, v//vn or v/vt/vn; negative indices count back from the last vertex.
        char* end = nullptr;
        const long i = std::strtol(corner.c_str(), &end, 10);
        if (end == corner.c_str() || i == 0) return bad("a face corner is not a vertex index");
        face.push_back(int(i > 0 ? i - 1 : long(mesh.vertices.size()) + i));
      }
      if (face.size() < 3) return bad("a face needs three corners");
      for (std::size_t j = 1; j + 1 < face.size(); ++j) {
        mesh.triangles.push_back({face[0], face[j], face[j + 1]});
        colours.push_back(colour);
      }
    } else if (tag == "mtllib") {
      std::string name;
      std::getline(s >> std::ws, name);
      const auto more = ReadMtl(std::filesystem::path(path).parent_path() / name);
      materials.insert(more.begin(), more.end());
    } else if (tag == "usemtl") {
      std::string name;
      s >> name;
      const auto it = materials.find(name);
      colour = it == materials.end() ? std::nullopt : std::optional(it->second);
      any_colour |= bool(colour);
    }
  }
  if (any_colour)
    for (const auto& c : colours)
      mesh.face_colours.push_back(c.value_or(std::array<std::uint8_t, 3>{160, 160, 160}));
  return mesh;
}

std::optional<Mesh> ReadStl(const std::string& path, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return Fail(error, path + ": cannot open: " + std::strerror(errno)), std::nullopt;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Mesh mesh;
  const auto add = [&](const float* v) {
    const int base = int(mesh.vertices.size());
    for (int j = 0; j < 3; ++j) mesh.vertices.emplace_back(v[3 * j], v[3 * j + 1], v[3 * j + 2]);
    mesh.triangles.push_back({base, base + 1, base + 2});
  };
  // Binary: an 80-byte header, a count, 50 bytes per triangle (normal, 3 corners, attribute).
  if (bytes.size() >= 84) {
    std::uint32_t count;
    std::memcpy(&count, bytes.data() + 80, 4);
    if (bytes.size() == 84 + std::size_t(count) * 50) {
      for (std::uint32_t t = 0; t < count; ++t) {
        float v[9];
        std::memcpy(v, bytes.data() + 84 + std::size_t(t) * 50 + 12, sizeof v);
        add(v);
      }
      return mesh;
    }
  }
  if (Lower(bytes.substr(0, 5)) != "solid")
    return Fail(error, path +
                           ": not an STL file (neither binary of the size its count says, "
                           "nor ASCII starting with 'solid')"),
           std::nullopt;
  std::istringstream s(bytes);
  std::string word;
  float v[9];
  int corner = 0;
  while (s >> word) {
    if (word != "vertex") continue;
    if (!(s >> v[3 * corner] >> v[3 * corner + 1] >> v[3 * corner + 2]))
      return Fail(error, path + ": a vertex needs three numbers"), std::nullopt;
    if (++corner == 3) add(v), corner = 0;
  }
  return mesh;
}

std::optional<Mesh> ReadPly(const std::string& path, std::string* error) {
  pcl::PolygonMesh polygons;
  pcl::console::VERBOSITY_LEVEL level = pcl::console::getVerbosityLevel();
  pcl::console::setVerbosityLevel(pcl::console::L_ALWAYS);  // our one line says it
  const int status = pcl::io::loadPLYFile(path, polygons);
  pcl::console::setVerbosityLevel(level);
  if (status < 0) return Fail(error, path + ": not a readable PLY file"), std::nullopt;
  Mesh mesh;
  const bool coloured =
      std::any_of(polygons.cloud.fields.begin(), polygons.cloud.fields.end(),
                  [](const pcl::PCLPointField& f) { return f.name == "rgb" || f.name == "rgba"; });
  pcl::PointCloud<pcl::PointXYZRGB> vertices;
  pcl::fromPCLPointCloud2(polygons.cloud, vertices);
  for (const auto& p : vertices.points) {
    mesh.vertices.emplace_back(p.x, p.y, p.z);
    if (coloured) mesh.vertex_colours.push_back({p.r, p.g, p.b});
  }
  for (const pcl::Vertices& face : polygons.polygons) {
    if (face.vertices.size() < 3) continue;
    for (std::size_t j = 1; j + 1 < face.vertices.size(); ++j)
      mesh.triangles.push_back(
          {int(face.vertices[0]), int(face.vertices[j]), int(face.vertices[j + 1])});
  }
  return mesh;
}

}  // namespace

bool IsMeshPath(const std::string& path) {
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  return ext == ".obj" || ext == ".ply" || ext == ".stl";
}

std::optional<Mesh> LoadMesh(const std::string& path, float scale, std::string* error) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    return Fail(error, path + ": no such file"), std::nullopt;
  const std::string ext = Lower(std::filesystem::path(path).extension().string());
  std::optional<Mesh> mesh;
  if (ext == ".obj")
    mesh = ReadObj(path, error);
  else if (ext == ".stl")
    mesh = ReadStl(path, error);
  else if (ext == ".ply")
    mesh = ReadPly(path, error);
  else
    return Fail(error, path + ": not a mesh Saccade reads (.obj, .ply or .stl)"), std::nullopt;
  if (!mesh) return std::nullopt;
  for (Eigen::Vector3f& v : mesh->vertices) v *= scale;
  std::string why;
  if (!IsValidMesh(*mesh, &why)) return Fail(error, path + ": " + why), std::nullopt;
  return mesh;
}

bool SaveMeshPly(const std::string& path, const Mesh& mesh, std::string* error) {
  if (!IsValidMesh(mesh, error)) return Fail(error, path + ": " + *error);
  std::vector<std::array<std::uint8_t, 3>> colours = mesh.vertex_colours;
  if (colours.empty() && !mesh.face_colours.empty()) {
    colours.assign(mesh.vertices.size(), {128, 128, 128});
    for (std::size_t t = mesh.triangles.size(); t-- > 0;)  // the first face using it wins
      for (int v : mesh.triangles[t]) colours[std::size_t(v)] = mesh.face_colours[t];
  }
  std::ostringstream out;
  out << "ply\nformat ascii 1.0\ncomment made by saccade, metres\nelement vertex "
      << mesh.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (!colours.empty()) out << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  out << "element face " << mesh.triangles.size()
      << "\nproperty list uchar int vertex_indices\nend_header\n";
  out.precision(9);
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Eigen::Vector3f& v = mesh.vertices[i];
    out << v.x() << ' ' << v.y() << ' ' << v.z();
    if (!colours.empty())
      out << ' ' << int(colours[i][0]) << ' ' << int(colours[i][1]) << ' ' << int(colours[i][2]);
    out << '\n';
  }
  for (const auto& t : mesh.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  return WriteBytes(path, out.str(), error);
}

}  // namespace saccade
