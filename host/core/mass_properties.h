// host/core/mass_properties.h: volume, centre of mass and inertia tensor of the shapes, at unit
// density; a body's mass or density scales them (host/world builds the BodyMass records).
#pragma once

#include <span>
#include <string>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/error.h"
#include "rubble/shared/body.h"

namespace rubble {

/// Mass properties of a solid of density 1 kg/m^3, in the shape's frame.
struct MassProperties {
    double volume = 0.0;         ///< m^3, equal to the mass at unit density
    glm::dvec3 centre{0.0};      ///< centre of mass, m
    glm::dmat3 inertia{0.0};     ///< inertia tensor about the centre of mass, kg m^2
};

/// A solid box with the given half extents (m), centred on the origin.
MassProperties boxMassProperties(glm::vec3 halfExtents);

/// A solid sphere of radius r (m), centred on the origin.
MassProperties sphereMassProperties(float radius);

/// A solid capsule centred on the origin: a cylinder of radius r and length 2 h along y, closed
/// by two hemispheres of radius r (m). Each hemisphere's inertia about the centre is its own
/// about its centre of mass, 83/320 m r^2 across, moved by the parallel-axis term to h + 3r/8.
MassProperties capsuleMassProperties(float radius, float halfHeight);

/// A closed triangle mesh whose triangles wind counter-clockwise seen from outside, by the
/// polyhedral integration of Eberly ("Polyhedral Mass Properties (Revisited)", 2002), which
/// reduces the volume integrals to sums over the triangles (divergence theorem). The volume is
/// negative when the winding is inward and meaningless when the mesh is not closed.
MassProperties polyhedronMassProperties(std::span<const glm::vec3> vertices,
                                        std::span<const glm::uvec3> triangles);

/// The inertia tensor of mp scaled from unit density to a total mass (kg).
glm::mat3 inertiaForMass(const MassProperties& mp, double mass);

/// Checks that a dynamic body's mass record holds normal, finite single-precision numbers: its
/// mass, inverse mass and the diagonals of its inertia and inverse inertia. A mass or a size at
/// the edge of the float range (a grain of 1e-30 kg, a box of 1e4 m with a mass of 1e30 kg) gives
/// a zero or an infinity there. Errors: BadInput at `where` (the body), naming `field` ("mass"
/// or "density").
Status checkMassRange(const shared::BodyMass& m, const std::string& where,
                      const std::string& field);

/// Principal moments and axes of a symmetric inertia tensor: I = R diag(moments) R^T, with R the
/// rotation of `axes` (a proper rotation, columns the principal axes in the tensor's frame).
struct PrincipalAxes {
    glm::dvec3 moments{0.0};
    glm::dquat axes{1.0, 0.0, 0.0, 0.0};
};

/// Diagonalises a symmetric 3x3 tensor by cyclic Jacobi rotations (Golub and Van Loan, 8.5).
PrincipalAxes principalAxes(const glm::dmat3& inertia);

} // namespace rubble
