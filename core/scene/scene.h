// Scene: what a user opens and saves — its objects (scene_objects.h: cages placed by
// transforms, instances, their sculpted displacement), the camera, the viewports and the
// tessellation settings — in a versioned JSON file.
//
// The schema, an example and the versioning/migration policy are in docs/scene-format.md.
// Each object's cage is either inline in the JSON or referenced by a path to an OBJ (with its
// tags in the OBJ), resolved relative to the scene file's directory. Version 1 files (one cage)
// load as a scene of one object.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>
#include <nlohmann/json.hpp>

#include "mesh/cage.h"
#include "mesh/result.h"
#include "scene/scene_objects.h"
#include "scene/shading.h"

namespace qp {

// The newest scene version this build reads and the only one it writes.
constexpr int kSceneVersion = 2;

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
    // The editor draws plain cage edges however short they project (it leaves them out where
    // they would be shorter than a few pixels: editor/app/cage_lines.h plainLinesReadable).
    bool denseCageLines = false;

    bool operator==(const DisplaySettings&) const = default;
};

struct Scene {
    // At least one once loaded or checked (validateObjects); in the order they are listed, drawn
    // and saved.
    std::vector<SceneObject> objects;
    std::optional<Camera> camera;   // absent: frame the model
    std::vector<Viewport> viewports{Viewport{}};
    Tessellation tessellation;
    DisplaySettings display;
    // The frames played and their rate; absent: the range of the objects' keys at 24 fps
    // (timelineOf).
    std::optional<Timeline> timeline;
};

// The scene's timeline, or the one its keys imply (frames 1..1 when nothing is keyed).
Timeline timelineOf(const Scene& scene);
// Whether any object has keys.
bool isAnimated(const Scene& scene);

// A scene of one object, `name`, holding `cage` (what opening a bare cage file gives).
Scene sceneOfCage(Cage cage, const std::string& name);

// The world-space bounds of every visible object (of every object when none is visible).
Bounds sceneBounds(const Scene& scene);

// `source` names the text in messages; `baseDir` resolves a referenced cage path.
Result<Scene> parseScene(std::string_view text, const std::string& source, const std::string& baseDir,
                         std::vector<std::string>* warnings = nullptr);
Result<Scene> loadScene(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Where a saved scene keeps its cages.
enum class CageStorage : uint8_t {
    Inline,      // every cage in the JSON
    Referenced,  // every cage in an OBJ beside the scene (savedCagePath), the JSON naming it
    AsLoaded,    // objects with a cagePath referenced, the others inline
};

// Pretty JSON. Referenced cages are written as their object's cagePath (Referenced: which must
// then be set for every object with a cage); the OBJs themselves are not written.
std::string formatScene(const Scene& scene, CageStorage storage);

// Checks the objects (validateObjects) and writes atomically. Referenced cages are saved first
// (atomically) as OBJs at savedCagePath relative to the scene file. OBJ sequences (kept absolute
// once read) are written relative to the scene file, so a scene saved to another folder still
// finds them.
Status saveScene(const Scene& scene, const std::string& path, CageStorage storage);

// The OBJ a referenced cage of object `index` is saved as (relative to the scene): its cagePath,
// or, when that is empty, "<scene name>.obj" (a scene of one object) or "<scene name>_<object
// name>.obj".
std::string savedCagePath(const Scene& scene, const std::string& scenePath, uint32_t index);

// Before saving to `path` a scene that was read from `readFrom` (empty: from nowhere): when they
// are different files, every referenced cage is renamed after the new scene (savedCagePath's
// "NAME.obj"), so that the files the scene was read from, its JSON and the OBJs it names, stay
// as they were instead of having their cages overwritten. Returns whether it renamed any.
bool nameCagesAfterNewScene(Scene& scene, const std::string& readFrom, const std::string& path);

// Loads a scene (.json) or a bare cage (.obj, wrapped in a scene of one object named after the
// file) by extension.
Result<Scene> loadSceneOrCage(const std::string& path, std::vector<std::string>* warnings = nullptr);

}  // namespace qp
