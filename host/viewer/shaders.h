// host/viewer/shaders.h: the GLSL 3.30 sources of the renderer's programs.
#pragma once

namespace rubble::viewer::shaders {

/// Instanced bodies, Blinn-Phong with one directional light and a sky/ground ambient term.
extern const char* const kBodyVertex;
extern const char* const kBodyFragment;
/// The ground: a square on a plane with an anti-aliased 1 m / 10 m grid, fading at its edge.
extern const char* const kGroundVertex;
extern const char* const kGroundFragment;
/// Coloured lines in the world (contacts, normals, AABBs, joints, axes).
extern const char* const kLineVertex;
extern const char* const kLineFragment;
/// Particles as round points scaled by distance.
extern const char* const kPointVertex;
extern const char* const kPointFragment;
/// Screen-space coloured triangles in pixels (text and its backdrop).
extern const char* const kOverlayVertex;
extern const char* const kOverlayFragment;

} // namespace rubble::viewer::shaders
