// include/rubble/shared/primitive_contact.h: contacts of spheres and planes with each other and
// with flattened hulls in stage narrowPhase, both pipelines (Ericson 4.3, 5.1, 5.2). Planes are
// solid below dot(n, x) = d.
#pragma once

#include "rubble/shared/clip.h"

RUBBLE_SHARED_BEGIN

// Sub-kinds of RUBBLE_KIND_PRIMITIVE ids (the high field).
#define RUBBLE_PRIMITIVE_WHOLE 0u
#define RUBBLE_PRIMITIVE_FACE 1u
#define RUBBLE_PRIMITIVE_EDGE 2u
#define RUBBLE_PRIMITIVE_VERTEX 3u

// Two spheres; the normal points from a to b, +y when the centres coincide.
RUBBLE_FN ContactManifold collideSpheresItem(float4 ca, float ra, float4 cb, float rb,
                                             float margin) {
    ContactManifold set = emptyContactsItem();
    const float4 d = sub4(cb, ca);
    const float dist = sqrt(dot3(d, d));
    const float s = dist - ra - rb;
    if (s > margin) return set;
    set.normal = dist > 1e-9f ? divide4(d, dist) : vec4(0.0f, 1.0f, 0.0f);
    const float4 onA = add4(ca, scale4(set.normal, ra)), onB = sub4(cb, scale4(set.normal, rb));
    addContactItem(&set, scale4(add4(onA, onB), 0.5f), -s,
                   makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, RUBBLE_PRIMITIVE_WHOLE, 0u));
    return set;
}

// A hull and a sphere whose centre is in the hull's frame; the normal points from the hull to
// the sphere.
RUBBLE_FN ContactManifold collideHullSphereItem(Hull hull, float4 c, float radius, float margin) {
    ContactManifold set = emptyContactsItem();
    // The face the centre is furthest above (or least below).
    uint top = 0;
    float above = RUBBLE_LOWEST_FLOAT;
    for (uint f = 0; f < hull.faceCount; ++f) {
        const float4 face = hull.faces[f];
        const float s = dot3(face, c) - face.w;
        if (s > above) {
            above = s;
            top = f;
        }
    }
    if (above - radius > margin) return set;
    if (above <= 0.0f) {
        // Inside: out through the face of least penetration.
        set.normal = faceNormalItem(hull.faces[top]);
        addContactItem(&set, sub4(c, scale4(set.normal, 0.5f * (above + radius))), radius - above,
                       makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, RUBBLE_PRIMITIVE_FACE, top));
        return set;
    }

    // Outside: the closest point lies on a face whose plane the centre is above.
    float best2 = 3.40282347e+38f;
    float4 closest = vec4(0.0f, 0.0f, 0.0f), normal = faceNormalItem(hull.faces[top]);
    uint kind = RUBBLE_PRIMITIVE_FACE, index = 0u;
    for (uint f = 0; f < hull.faceCount; ++f) {
        const float4 face = hull.faces[f];
        const float4 faceNormal = faceNormalItem(face);
        const float s = dot3(face, c) - face.w;
        if (s <= 0.0f) continue;
        const float4 projected = sub4(c, scale4(faceNormal, s));
        int inside = 1;
        const uint first = hull.faceEdge[f];
        uint h = first;
        do {
            const float4 v0 = hull.vertices[hull.edges[h].origin];
            const float4 v1 = hull.vertices[hull.edges[hull.edges[h].next].origin];
            if (dot3(cross3(sub4(v1, v0), faceNormal), sub4(projected, v0)) > 0.0f) {
                inside = 0;
                // The closest point of the edge to c.
                const float4 e = sub4(v1, v0);
                const float e2 = dot3(e, e);
                const float t = e2 > 0.0f ? clampItem(dot3(sub4(c, v0), e) / e2, 0.0f, 1.0f) : 0.0f;
                const float4 q = add4(v0, scale4(e, t));
                const float4 cq = sub4(c, q);
                const float d2 = dot3(cq, cq);
                if (d2 < best2) {
                    best2 = d2;
                    closest = q;
                    normal = d2 > 1e-12f ? glmNormalize(cq) : faceNormal;
                    if (t <= 0.0f || t >= 1.0f) {
                        kind = RUBBLE_PRIMITIVE_VERTEX;
                        index = t <= 0.0f ? hull.edges[h].origin : hull.edges[hull.edges[h].next].origin;
                    } else {
                        kind = RUBBLE_PRIMITIVE_EDGE;
                        index = h / 2u;
                    }
                }
            }
            h = hull.edges[h].next;
        } while (h != first);
        if (inside && s * s < best2) {
            best2 = s * s;
            closest = projected;
            normal = faceNormal;
            kind = RUBBLE_PRIMITIVE_FACE;
            index = f;
        }
    }
    const float dist = sqrt(best2);
    if (dist - radius > margin) return set;
    set.normal = normal;
    const float4 onSphere = sub4(c, scale4(set.normal, radius));
    addContactItem(&set, scale4(add4(closest, onSphere), 0.5f), radius - dist,
                   makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, kind, index));
    return set;
}

// A plane and a sphere; the normal is the plane's.
RUBBLE_FN ContactManifold collidePlaneSphereItem(float4 n, float offset, float4 c, float radius,
                                                 float margin) {
    ContactManifold set = emptyContactsItem();
    const float s = dot3(n, c) - offset - radius;
    if (s > margin) return set;
    set.normal = n;
    addContactItem(&set, sub4(c, scale4(n, radius + 0.5f * s)), -s,
                   makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, RUBBLE_PRIMITIVE_WHOLE, 0u));
    return set;
}

// Vertex v of a hull as a hull-plane candidate: at (position, depth) when within the margin.
RUBBLE_FN LocalContact planeCandidateItem(Hull hull, float4 n, float offset, uint v) {
    const float4 x = hull.vertices[v];
    const float s = dot3(n, x) - offset;
    LocalContact c;
    c.position = sub4(x, scale4(n, 0.5f * s));
    c.depth = -s;
    c.feature = makeFeatureIdItem(RUBBLE_KIND_PRIMITIVE, RUBBLE_PRIMITIVE_VERTEX, v);
    c.pad0 = 0u;
    c.pad1 = 0u;
    return c;
}

// reduceContactsItem over the vertices within the margin of a plane, in vertex order, without
// storing them (a hull may have any number on the plane): the same picks as the candidates
// listed and reduced. Writes vertex indices to keep; returns how many.
RUBBLE_FN uint reducePlaneCandidatesItem(Hull hull, float4 n, float offset, float margin,
                                         uint* keep) {
    uint count = 0;
    for (uint v = 0; v < hull.vertexCount; ++v) {
        if (dot3(n, hull.vertices[v]) - offset > margin) continue;
        if (count < RUBBLE_MAX_CONTACT_POINTS) keep[count] = v;
        ++count;
    }
    if (count <= RUBBLE_MAX_CONTACT_POINTS) return count;
    // The deepest (the first of equals), then as reduceContactsItem.
    uint first = keep[0];
    float firstDepth = planeCandidateItem(hull, n, offset, first).depth;
    for (uint v = 0; v < hull.vertexCount; ++v) {
        if (dot3(n, hull.vertices[v]) - offset > margin) continue;
        const float depth = planeCandidateItem(hull, n, offset, v).depth;
        if (depth > firstDepth) {
            firstDepth = depth;
            first = v;
        }
    }
    keep[0] = first;
    const float4 p0 = planeCandidateItem(hull, n, offset, first).position;
    uint second = first;
    float far2 = 0.0f;
    for (uint v = 0; v < hull.vertexCount; ++v) {
        if (dot3(n, hull.vertices[v]) - offset > margin) continue;
        const float4 d = sub4(planeCandidateItem(hull, n, offset, v).position, p0);
        if (dot3(d, d) > far2) {
            far2 = dot3(d, d);
            second = v;
        }
    }
    if (second == first) return 1u;
    keep[1] = second;
    const float4 p1 = planeCandidateItem(hull, n, offset, second).position;
    uint third = first;
    float best = 0.0f;
    for (uint v = 0; v < hull.vertexCount; ++v) {
        if (dot3(n, hull.vertices[v]) - offset > margin) continue;
        const float4 q = planeCandidateItem(hull, n, offset, v).position;
        const float a = fabs(contactAreaItem(p0, p1, q, n));
        if (a > best) {
            best = a;
            third = v;
        }
    }
    const float tiny = 1e-6f * far2;
    if (third == first || best <= tiny) return 2u;
    keep[2] = third;
    const float4 p2 = planeCandidateItem(hull, n, offset, third).position;
    const float side = contactAreaItem(p0, p1, p2, n) > 0.0f ? 1.0f : -1.0f;
    uint fourth = first;
    best = tiny;
    for (uint v = 0; v < hull.vertexCount; ++v) {
        if (dot3(n, hull.vertices[v]) - offset > margin) continue;
        const float4 q = planeCandidateItem(hull, n, offset, v).position;
        const float added = max3Item(-side * contactAreaItem(p0, p1, q, n),
                                     -side * contactAreaItem(p1, p2, q, n),
                                     -side * contactAreaItem(p2, p0, q, n));
        if (added > best) {
            best = added;
            fourth = v;
        }
    }
    if (fourth == first) return 3u;
    keep[3] = fourth;
    return 4u;
}

// A plane in the hull's frame and the hull; the normal is the plane's.
RUBBLE_FN ContactManifold collidePlaneHullItem(float4 n, float offset, Hull hull, float margin) {
    ContactManifold set = emptyContactsItem();
    set.normal = n;
    // The deepest vertex settles a hull that stays clear.
    const uint deepest = supportVertexItem(hull, negate4(n), 0u);
    if (dot3(n, hull.vertices[deepest]) - offset > margin) return set;
    uint keep[RUBBLE_MAX_CONTACT_POINTS];
    const uint kept = reducePlaneCandidatesItem(hull, n, offset, margin, keep);
    for (uint i = 0; i < kept; ++i) {
        const LocalContact c = planeCandidateItem(hull, n, offset, keep[i]);
        addContactItem(&set, c.position, c.depth, c.feature);
    }
    return set;
}

RUBBLE_SHARED_END
