#pragma once
// A glTF 2.0 file as a whole scene (docs/usage.md, "Rendering", its glTF
// paragraphs): `nuld render FILE.glb`, or a scene file's "gltf" entry,
// which adds render settings, an environment and emitters to it.
//
//  - Geometry: the default scene's nodes with their transforms
//    (gltf_loader.h).
//  - Camera: the first perspective camera a node places; its yfov spans the
//    image's height, its aspectRatio sets the film (512 pixels wide).
//    Without one, a documented default view: looking down -z at the centre
//    of the geometry's bounds (glTF's front faces +z), 40 degrees wide,
//    framing its bounding sphere.
//  - Materials: metallic-roughness onto the Disney parameters: base colour,
//    metallic and roughness factors times their textures (colour decoded
//    from sRGB; TEXCOORD_0); specular from KHR_materials_ior's F0 times
//    KHR_materials_specular's factor and colour factor's largest component
//    (F0 = 0.08 specular, 0.04 at ior 1.5);
//    KHR_materials_transmission as spec_trans with the ior; and
//    KHR_materials_clearcoat's factor and roughness as clearcoat and the
//    gloss of equal GGX alpha. A primitive without a material takes glTF's
//    default (white, metallic 1, roughness 1).
//  - Lights: an emissive material (emissiveFactor times
//    KHR_materials_emissive_strength) makes its meshes area lights, two-
//    sided when the material is; KHR_lights_punctual's point, spot and
//    directional lights, their intensity read as radiant (intensity per
//    steradian in the scene's radiance units, irradiance for directional
//    lights), as glTF's own viewers read it against emissive values.
//  - What the file holds that nuld does not use is named in one warning.
//
// Errors name the file and the field (gltf_loader.h), as the scene files do.

#include <string>

#include "scenes/gltf_loader.h"  // isGltfPath
#include "scenes/scene_file.h"

namespace nuld {

// The scene of a glTF file: geometry, materials, camera, film size and
// lights; no environment, and its light choice not yet built (the caller
// adds what it has and calls finishLights).
LoadedScene loadGltfScene(const std::string &path, const SceneChoices &choices);

}  // namespace nuld
