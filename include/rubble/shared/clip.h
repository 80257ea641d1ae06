// include/rubble/shared/clip.h: the geometric steps of manifold building in stage narrowPhase
// (both pipelines): Sutherland-Hodgman clipping with feature tags, reduction to four points,
// closest points of two segments, feature ids (Gregorius, GDC 2015; Ericson 5.1.9). Buffers are
// the caller's (private memory on the device).
#pragma once

#include "rubble/shared/hull.h"

RUBBLE_SHARED_BEGIN

// Contacts are made while the shapes are closer than this, m.
#define RUBBLE_CONTACT_MARGIN 0.004f
// A manifold never holds more points than this.
#define RUBBLE_MAX_CONTACT_POINTS 4u
// A clip segment tag with this bit runs along the clip line of a reference half-edge.
#define RUBBLE_CLIP_LINE_TAG 0x4000u

// Feature id kinds, the top two bits.
#define RUBBLE_KIND_FACE_A 0u
#define RUBBLE_KIND_FACE_B 1u
#define RUBBLE_KIND_EDGES 2u
#define RUBBLE_KIND_PRIMITIVE 3u

// 2 bits of kind, then two 15-bit fields.
RUBBLE_FN uint makeFeatureIdItem(uint kind, uint high, uint low) {
    return (kind << 30) | ((high & 0x7FFFu) << 15) | (low & 0x7FFFu);
}

// A vertex of the polygon being clipped.
typedef struct ClipVertex {
    float4 position;
    uint clipEdge; // reference half-edge + 1 whose plane made it; 0: an original
    uint tag;      // the incident segment it sits on
    uint segment;  // tag of the segment that starts here
    uint pad;
} ClipVertex;

// One contact point in the frame of its set.
typedef struct LocalContact {
    float4 position; // midway between the two surfaces, m
    float depth;     // penetration along the normal, m (negative: a gap)
    uint feature;
    uint pad0, pad1;
} LocalContact;

// Clipping buffers, the caller's: polygon and scratch each with room for an incident face's
// vertices plus one per reference edge plus one, candidates as many (RUBBLE_CLIP_CAPACITY on the
// device; the host sizes them from its largest face, HullData::largestFace).
typedef struct ClipBuffers {
    ClipVertex* polygon;
    ClipVertex* scratch;
    LocalContact* candidates;
} ClipBuffers;

// 112 bytes: up to four contacts sharing one normal, from body a to body b. The narrow phase
// works with it in a shape's frame; kernels/sat.cl writes it in the world frame, one per pair.
typedef struct ContactManifold {
    float4 normal;    // unit, from a to b (w = 0)
    float4 points[4]; // position, midway between the surfaces, m (xyz); depth, m (w; < 0: a gap)
    uint features[4]; // feature ids (makeFeatureIdItem), unique within the manifold
    uint a, b;        // body indices, a < b (the pair's)
    uint count;       // points in use, 0 to 4
    uint pad0;
} ContactManifold;
RUBBLE_STATIC_ASSERT_SIZE(ContactManifold, 112);

RUBBLE_FN ContactManifold emptyContactsItem(void) {
    ContactManifold m;
    m.normal = vec4(0.0f, 1.0f, 0.0f);
    for (uint i = 0; i < RUBBLE_MAX_CONTACT_POINTS; ++i) {
        m.points[i] = make4(0.0f, 0.0f, 0.0f, 0.0f);
        m.features[i] = 0u;
    }
    m.a = 0u;
    m.b = 0u;
    m.count = 0u;
    m.pad0 = 0u;
    return m;
}

// Appends a point while there is room.
RUBBLE_FN void addContactItem(ContactManifold* m, float4 position, float depth, uint feature) {
    if (m->count >= RUBBLE_MAX_CONTACT_POINTS) return;
    m->points[m->count] = make4(position.x, position.y, position.z, depth);
    m->features[m->count] = feature;
    ++m->count;
}

// One Sutherland-Hodgman pass: the part of the closed polygon in[0..n) where
// dot(normal, x) <= offset, into out (room for n + 1); returns the vertices written.
RUBBLE_FN uint clipPolygonItem(const ClipVertex* in, uint n, float4 normal, float offset,
                               uint clipEdge, ClipVertex* out) {
    uint count = 0;
    if (n == 0u) return 0u;
    ClipVertex p = in[n - 1u];
    float dp = dot3(normal, p.position) - offset;
    for (uint i = 0; i < n; ++i) {
        const ClipVertex q = in[i];
        const float dq = dot3(normal, q.position) - offset;
        if ((dp <= 0.0f) != (dq <= 0.0f)) {
            ClipVertex x;
            x.position = add4(p.position, scale4(sub4(q.position, p.position), dp / (dp - dq)));
            x.clipEdge = clipEdge + 1u;
            x.tag = p.segment;
            x.segment = dp > 0.0f ? p.segment : (RUBBLE_CLIP_LINE_TAG | clipEdge);
            x.pad = 0u;
            out[count++] = x;
        }
        if (dq <= 0.0f) out[count++] = q;
        p = q;
        dp = dq;
    }
    return count;
}

// Twice the signed area of triangle (a, b, c) about the normal.
RUBBLE_FN float contactAreaItem(float4 a, float4 b, float4 c, float4 normal) {
    return dot3(cross3(sub4(b, a), sub4(c, a)), normal);
}

// The largest of three as std::max({x, y, z}) picks it.
RUBBLE_FN float max3Item(float x, float y, float z) {
    float m = x;
    if (m < y) m = y;
    if (m < z) m = z;
    return m;
}

// Picks at most four of points[0..n): the deepest, the furthest from it, the
// largest triangle with those two, the most area added beyond it. Writes indices to keep.
RUBBLE_FN uint reduceContactsItem(const LocalContact* points, uint n, float4 normal, uint* keep) {
    if (n <= RUBBLE_MAX_CONTACT_POINTS) {
        for (uint i = 0; i < n; ++i) keep[i] = i;
        return n;
    }
    uint first = 0;
    for (uint i = 1; i < n; ++i)
        if (points[i].depth > points[first].depth) first = i;
    keep[0] = first;
    const float4 p0 = points[first].position;

    uint second = first;
    float far2 = 0.0f;
    for (uint i = 0; i < n; ++i) {
        const float4 d = sub4(points[i].position, p0);
        if (dot3(d, d) > far2) {
            far2 = dot3(d, d);
            second = i;
        }
    }
    if (second == first) return 1u;
    keep[1] = second;
    const float4 p1 = points[second].position;

    uint third = first;
    float best = 0.0f;
    for (uint i = 0; i < n; ++i) {
        const float a = fabs(contactAreaItem(p0, p1, points[i].position, normal));
        if (a > best) {
            best = a;
            third = i;
        }
    }
    const float tiny = 1e-6f * far2;
    if (third == first || best <= tiny) return 2u;
    keep[2] = third;
    const float4 p2 = points[third].position;
    const float side = contactAreaItem(p0, p1, p2, normal) > 0.0f ? 1.0f : -1.0f;

    uint fourth = first;
    best = tiny;
    for (uint i = 0; i < n; ++i) {
        const float4 q = points[i].position;
        const float added = max3Item(-side * contactAreaItem(p0, p1, q, normal),
                                     -side * contactAreaItem(p1, p2, q, normal),
                                     -side * contactAreaItem(p2, p0, q, normal));
        if (added > best) {
            best = added;
            fourth = i;
        }
    }
    if (fourth == first) return 3u;
    keep[3] = fourth;
    return 4u;
}

// The closest points of two segments.
typedef struct SegmentPoints {
    float4 c1, c2;
} SegmentPoints;

RUBBLE_FN SegmentPoints closestPointsOnSegmentsItem(float4 p1, float4 q1, float4 p2, float4 q2) {
    const float epsilon = 1e-12f;
    const float4 d1 = sub4(q1, p1), d2 = sub4(q2, p2), r = sub4(p1, p2);
    const float a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r);
    float s = 0.0f, t = 0.0f;
    if (a <= epsilon && e <= epsilon) {
        s = 0.0f;
        t = 0.0f;
    } else if (a <= epsilon) {
        t = clampItem(f / e, 0.0f, 1.0f);
    } else {
        const float c = dot3(d1, r);
        if (e <= epsilon) {
            s = clampItem(-c / a, 0.0f, 1.0f);
        } else {
            const float b = dot3(d1, d2), denom = a * e - b * b;
            s = denom > 0.0f ? clampItem((b * f - c * e) / denom, 0.0f, 1.0f) : 0.0f;
            t = (b * s + f) / e;
            if (t < 0.0f) {
                t = 0.0f;
                s = clampItem(-c / a, 0.0f, 1.0f);
            } else if (t > 1.0f) {
                t = 1.0f;
                s = clampItem((b - c) / a, 0.0f, 1.0f);
            }
        }
    }
    SegmentPoints sp;
    sp.c1 = add4(p1, scale4(d1, s));
    sp.c2 = add4(p2, scale4(d2, t));
    return sp;
}

RUBBLE_SHARED_END
