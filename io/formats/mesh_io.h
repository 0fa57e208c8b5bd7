// Reading meshes (`saccade model --mesh`): Wavefront OBJ (with its MTL's diffuse colours per
// face), PLY (ASCII or binary, vertex colours kept) and STL (ASCII or binary); writing them as
// PLY (`saccade model --synthetic`). Every failure comes back as one line naming the file.
#pragma once

#include "core/mesh.h"

#include <optional>
#include <string>

namespace saccade {

/// True when `path` names a mesh by its extension (.obj, .ply or .stl, any case).
bool IsMeshPath(const std::string& path);

/// The mesh in `path`, its coordinates multiplied by `scale` (0.001 for a file in millimetres),
/// polygons split into triangles. Checked with IsValidMesh.
std::optional<Mesh> LoadMesh(const std::string& path, float scale, std::string* error);

/// Writes the mesh as an ASCII PLY file (metres; a colour per vertex when it has one, a face's
/// colour given to its vertices when only faces have one), whole or not at all (WriteBytes).
bool SaveMeshPly(const std::string& path, const Mesh& mesh, std::string* error);

}  // namespace saccade
