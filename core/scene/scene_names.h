// The names the scene file gives enumerated values, shared by its reader (scene.cpp) and its
// writer (scene_write.cpp). Internal to core.
#pragma once

#include <cassert>
#include <span>

#include "scene/scene.h"

namespace qp::scene_names {

inline constexpr const char* kFormatName = "quadplan-scene";

template <class E>
struct EnumName {
    const char* name;
    E value;
};

inline constexpr EnumName<BoundaryInterpolation> kBoundaryNames[] = {
    {"edges-and-corners", BoundaryInterpolation::EdgesAndCorners},
    {"edges-only", BoundaryInterpolation::EdgesOnly},
    {"none", BoundaryInterpolation::None}};
inline constexpr EnumName<CreaseMethod> kCreaseMethodNames[] = {
    {"normal", CreaseMethod::Normal}, {"chaikin", CreaseMethod::Chaikin}};
inline constexpr EnumName<TriangleSubdivision> kTriangleNames[] = {
    {"catmark", TriangleSubdivision::Catmark}, {"smooth", TriangleSubdivision::Smooth}};
inline constexpr EnumName<FVarInterpolation> kFVarNames[] = {
    {"none", FVarInterpolation::None},
    {"corners-only", FVarInterpolation::CornersOnly},
    {"corners-plus1", FVarInterpolation::CornersPlus1},
    {"corners-plus2", FVarInterpolation::CornersPlus2},
    {"boundaries", FVarInterpolation::Boundaries},
    {"all", FVarInterpolation::All}};
inline constexpr EnumName<Projection> kProjectionNames[] = {
    {"perspective", Projection::Perspective}, {"orthographic", Projection::Orthographic}};
inline constexpr EnumName<CameraLink> kCameraLinkNames[] = {
    {"linked", CameraLink::Linked}, {"independent", CameraLink::Independent}};
inline constexpr EnumName<TessellationMode> kTessellationModeNames[] = {
    {"uniform", TessellationMode::Uniform}, {"adaptive", TessellationMode::Adaptive}};
inline constexpr EnumName<UpAxis> kUpAxisNames[] = {{"y", UpAxis::Y}, {"z", UpAxis::Z}};
inline constexpr EnumName<Interpolation> kInterpolationNames[] = {
    {"linear", Interpolation::Linear}, {"catmull-rom", Interpolation::CatmullRom}};
inline constexpr EnumName<Shading> kShadingNames[] = {{"studio", Shading::Studio}, {"matcap", Shading::Matcap}};

template <class E>
const char* enumName(std::span<const EnumName<E>> names, E value) {
    for (const EnumName<E>& n : names)
        if (n.value == value) return n.name;
    assert(false && "enum value missing from its name table");
    return "";
}

}  // namespace qp::scene_names
