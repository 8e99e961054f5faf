// COLLADA meshes through assimp (see mesh_import.hpp).
#include "io/mesh_import.hpp"

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>

namespace fulcrum::detail {

std::optional<ImportedMesh> importColladaMesh(const std::filesystem::path& file, std::string& why) {
    Assimp::Importer importer;
    // Points and lines are dropped: a collider or a visual needs triangles.
    importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
    // PreTransformVertices bakes every node's transform (the file's unit and
    // up axis sit in the root node's) into the vertices.
    const aiScene* scene = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                                                aiProcess_PreTransformVertices | aiProcess_SortByPType);
    if (scene == nullptr) {
        why = std::string("assimp cannot read it: ") + importer.GetErrorString();
        return std::nullopt;
    }
    ImportedMesh out;
    for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        if ((mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
        const auto base = static_cast<std::uint32_t>(out.vertices.size());
        for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
            const aiVector3D& p = mesh->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                why = "it holds a non-finite vertex";
                return std::nullopt;
            }
            // assimp's y up -> z up: a quarter turn about x, (x, y, z) -> (x, -z, y).
            out.vertices.push_back({static_cast<Real>(p.x), static_cast<Real>(-p.z), static_cast<Real>(p.y)});
        }
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
            const aiFace& face = mesh->mFaces[f];
            if (face.mNumIndices != 3) continue;
            out.triangles.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
        if (!out.color && mesh->mMaterialIndex < scene->mNumMaterials) {
            const aiMaterial* material = scene->mMaterials[mesh->mMaterialIndex];
            aiString name;
            aiColor4D c;
            // assimp's stand-in for a mesh without a material is no colour of the file's.
            const bool standIn = material->Get(AI_MATKEY_NAME, name) == AI_SUCCESS && name == aiString(AI_DEFAULT_MATERIAL_NAME);
            if (!standIn && material->Get(AI_MATKEY_COLOR_DIFFUSE, c) == AI_SUCCESS) {
                out.color = std::array<float, 4>{c.r, c.g, c.b, c.a};
            }
        }
    }
    if (out.triangles.empty()) {
        why = "it holds no triangles";
        return std::nullopt;
    }
    return out;
}

}  // namespace fulcrum::detail
