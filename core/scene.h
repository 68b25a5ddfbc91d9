// Scene: everything a user saves besides the cage itself — the camera, the viewports, the
// tessellation settings and the sculpted displacement — in a versioned JSON file.
//
// The schema, an example and the versioning/migration policy are in docs/scene-format.md.
// The cage is either inline in the JSON or referenced by a path to an OBJ (with its tags in
// the OBJ), resolved relative to the scene file's directory.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "cage.h"
#include "displacement.h"
#include "result.h"
#include "shading.h"

namespace qp {

// The newest scene version this build reads and the only one it writes.
constexpr int kSceneVersion = 1;

enum class Projection : uint8_t { Perspective, Orthographic };

struct Camera {
    glm::vec3 eye{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovYDegrees = 45.0f;  // perspective
    Projection projection = Projection::Perspective;
    float orthoHeight = 2.0f;  // orthographic: world-space height of the view

    bool operator==(const Camera&) const = default;
};

enum class CameraLink : uint8_t { Linked, Independent };

struct Viewport {
    // Scheme and colouring names are open-ended (plugins add their own); never empty.
    std::string scheme = "plans";
    CameraLink camera = CameraLink::Linked;
    std::string colorBy = "shading";

    bool operator==(const Viewport&) const = default;
};

enum class TessellationMode : uint8_t { Uniform, Adaptive };

struct Tessellation {
    TessellationMode mode = TessellationMode::Adaptive;
    int factor = 8;               // uniform: segments per face edge, 1..64
    float pixelsPerEdge = 8.0f;   // adaptive: target on-screen length of a tessellated edge
    bool showCage = true;
    bool showWireframe = false;

    bool operator==(const Tessellation&) const = default;
};

// The world axis that points up: the ground grid lies across it, the camera orbits about it.
enum class UpAxis : uint8_t { Y, Z };

struct DisplaySettings {
    std::optional<UpAxis> upAxis;  // absent (older files): the viewer guesses from the cage
    Shading shading = Shading::Studio;
    bool showGrid = true;          // the ground grid

    bool operator==(const DisplaySettings&) const = default;
};

struct Scene {
    Cage cage;
    std::string cagePath;           // as written in the scene file; empty when the cage is inline
    std::optional<Camera> camera;   // absent: frame the model
    std::vector<Viewport> viewports{Viewport{}};
    Tessellation tessellation;
    DisplaySettings display;
    // Sculpted displacement over the cage's sub-faces (displacement.h); empty: none. Its layout
    // follows the cage's topology: rebuild it (resampleDisplacement, makeDisplacement) after
    // topology edits.
    Displacement displacement;
};

// `source` names the text in messages; `baseDir` resolves a referenced cage path.
Result<Scene> parseScene(std::string_view text, const std::string& source, const std::string& baseDir,
                         std::vector<std::string>* warnings = nullptr);
Result<Scene> loadScene(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Pretty JSON. With inlineCage false the cage is written as a reference to scene.cagePath
// (which must then be set); the OBJ itself is not written.
std::string formatScene(const Scene& scene, bool inlineCage);

// Writes atomically. With inlineCage false the cage is also saved (atomically) as an OBJ at
// scene.cagePath relative to the scene file, or at "<scene name>.obj" beside it when
// cagePath is empty.
Status saveScene(const Scene& scene, const std::string& path, bool inlineCage);

// Loads a scene (.json) or a bare cage (.obj, wrapped in a default Scene) by extension.
Result<Scene> loadSceneOrCage(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace qp
