// tests/support/level_cases.h: cases the CPU's and the device's level-mesh tests share: grids of
// triangles (as a mesh or an OBJ), and a box sliding over one against the same box on a plane.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include <glm/glm.hpp>
#include <gtest/gtest.h>

#include "host/geometry/obj_mesh.h"
#include "rubble/world.h"
#include "support/test_util.h"

namespace rubble::test {

/// A grid of n x n quads of side `cell` centred on the origin, facing up (two triangles a quad),
/// its vertex at (x, z) at the height `height(x, z)`.
template <class Height> TriangleMesh quadGrid(int n, float cell, Height height) {
    TriangleMesh m;
    const float x0 = -0.5f * cell * float(n);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const float x = x0 + cell * float(i), z = x0 + cell * float(j);
            m.vertices.emplace_back(x, height(x, z), z);
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const auto a = std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 1),
                       d = c + 1;
            m.triangles.emplace_back(a, c, b);
            m.triangles.emplace_back(b, c, d);
        }
    return m;
}

/// An OBJ of a flat grid of n x n quads of side `cell` at y = 0, centred on the origin, facing
/// up (two triangles a quad).
inline std::string flatGridObj(int n, float cell) {
    std::ostringstream obj;
    const float x0 = -0.5f * cell * float(n);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            obj << "v " << x0 + cell * float(i) << " 0 " << x0 + cell * float(j) << "\n";
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 1, d = c + 1;
            obj << "f " << a << " " << c << " " << b << "\nf " << b << " " << c << " " << d << "\n";
        }
    return obj.str();
}

/// The body `crate` (friction 0.3 against the floor) settles for 60 steps on `plane` and on
/// `mesh`, then leaves at 5 m/s along x and slides 45 steps (0.75 s at 60 Hz; it stops after
/// about 1.7 s): on the mesh it never moves vertically faster than 1 mm/s (no bump on the
/// seams), and both decelerate at 0.3 g within 1%, the mesh as the plane.
inline void expectSlidesAsOnAPlane(World& plane, World& mesh, std::uint32_t crate) {
    for (World* w : {&plane, &mesh}) {
        ASSERT_TRUE(stepWorld(*w, 60)); // settle
        ASSERT_TRUE(w->setVelocity(crate, glm::vec3(5.0f, 0.0f, 0.0f), glm::vec3(0.0f)).ok());
    }
    const int steps = 45;
    float worstVertical = 0.0f;
    for (int i = 0; i < steps; ++i) {
        ASSERT_TRUE(stepWorld(plane, 1));
        ASSERT_TRUE(stepWorld(mesh, 1));
        worstVertical = std::max(worstVertical, std::abs(mesh.body(crate).linearVelocity.y));
    }
    EXPECT_LT(worstVertical, 1e-3f) << "m/s: the box bumps on the seams";
    const float t = float(steps) / 60.0f;
    const float planeDecel = (5.0f - plane.body(crate).linearVelocity.x) / t;
    const float meshDecel = (5.0f - mesh.body(crate).linearVelocity.x) / t;
    EXPECT_NEAR(planeDecel, 0.3f * 9.81f, 0.01f * 0.3f * 9.81f);
    EXPECT_NEAR(meshDecel, planeDecel, 0.01f * planeDecel);
    EXPECT_LT(std::abs(mesh.body(crate).linearVelocity.z), 1e-3f);
}

} // namespace rubble::test
