// host/collision/primitive_contact.h: contacts of spheres and planes with each other and with
// hulls, part of CPU stage narrowPhase (Ericson, "Real-Time Collision Detection", 4.3, 5.1, 5.2).
// Pure; each works in one frame that the caller chooses. Planes are solid below dot(n, x) = d.
#pragma once

#include <glm/glm.hpp>

#include "host/collision/contact_set.h"
#include "host/geometry/half_edge.h"

namespace rubble {

/// Two spheres; the normal points from a to b (up, +y, when the centres coincide).
ContactSet collideSpheres(glm::vec3 centreA, float radiusA, glm::vec3 centreB, float radiusB,
                          float margin = kContactMargin);

/// A hull and a sphere whose centre is in the hull's frame; the normal points from the hull to
/// the sphere. The closest point of the hull is on a face, an edge or a vertex that the centre
/// sees; a centre inside leaves through the face of least penetration.
ContactSet collideHullSphere(const HalfEdgeMesh& hull, glm::vec3 centre, float radius,
                             float margin = kContactMargin);

/// A plane (unit normal, offset) and a sphere; the normal is the plane's, from plane to sphere.
ContactSet collidePlaneSphere(glm::vec3 normal, float offset, glm::vec3 centre, float radius,
                              float margin = kContactMargin);

/// A plane given in the hull's frame and the hull; the normal is the plane's, from plane to hull.
/// Every vertex closer than the margin is a candidate; at most four are kept (clip.h).
ContactSet collidePlaneHull(glm::vec3 normal, float offset, const HalfEdgeMesh& hull,
                            float margin = kContactMargin);

} // namespace rubble
