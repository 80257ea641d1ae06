// host/collision/clip.cpp: clipping, contact reduction and segment closest points for the
// manifolds of CPU stage narrowPhase (Gregorius 2015; Ericson 5.1.9). No allocation.
#include "host/collision/clip.h"

#include <algorithm>
#include <cmath>

namespace rubble {

std::size_t clipPolygon(std::span<const ClipVertex> in, glm::vec3 normal, float offset,
                        std::uint32_t clipEdge, std::span<ClipVertex> out) {
    std::size_t n = 0;
    if (in.empty()) return 0;
    ClipVertex p = in.back();
    float dp = glm::dot(normal, p.position) - offset;
    for (const ClipVertex& q : in) {
        const float dq = glm::dot(normal, q.position) - offset;
        if ((dp <= 0.0f) != (dq <= 0.0f)) {
            // The segment p-q crosses the plane: a new vertex on it.
            ClipVertex x;
            x.position = p.position + (q.position - p.position) * (dp / (dp - dq));
            x.clipEdge = clipEdge + 1;
            x.tag = p.segment;
            // Entering, the rest of p-q follows; leaving, the clip line follows.
            x.segment = dp > 0.0f ? p.segment : (kClipLineTag | clipEdge);
            out[n++] = x;
        }
        if (dq <= 0.0f) out[n++] = q;
        p = q;
        dp = dq;
    }
    return n;
}

std::uint32_t reduceContacts(std::span<const LocalContact> points, glm::vec3 normal,
                             std::array<std::uint32_t, kMaxContactPoints>& keep) {
    const std::size_t n = points.size();
    if (n <= kMaxContactPoints) {
        for (std::uint32_t i = 0; i < n; ++i) keep[i] = i;
        return std::uint32_t(n);
    }
    // The deepest point: the one the solver needs most.
    std::uint32_t first = 0;
    for (std::uint32_t i = 1; i < n; ++i)
        if (points[i].depth > points[first].depth) first = i;
    keep[0] = first;
    const glm::vec3 p0 = points[first].position;

    // The furthest from it.
    std::uint32_t second = first;
    float far2 = 0.0f;
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::vec3 d = points[i].position - p0;
        if (glm::dot(d, d) > far2) {
            far2 = glm::dot(d, d);
            second = i;
        }
    }
    if (second == first) return 1;
    keep[1] = second;
    const glm::vec3 p1 = points[second].position;

    // Twice the signed area of triangle (a, b, c) about the normal.
    auto area = [normal](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
        return glm::dot(glm::cross(b - a, c - a), normal);
    };
    // The largest triangle with the first two, on either side.
    std::uint32_t third = first;
    float best = 0.0f;
    for (std::uint32_t i = 0; i < n; ++i) {
        const float a = std::fabs(area(p0, p1, points[i].position));
        if (a > best) {
            best = a;
            third = i;
        }
    }
    const float tiny = 1e-6f * far2;
    if (third == first || best <= tiny) return 2;
    keep[2] = third;
    const glm::vec3 p2 = points[third].position;
    const float side = area(p0, p1, p2) > 0.0f ? 1.0f : -1.0f;

    // The point outside the triangle that adds the most area beyond one of its edges.
    std::uint32_t fourth = first;
    best = tiny;
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::vec3 q = points[i].position;
        const float added =
            std::max({-side * area(p0, p1, q), -side * area(p1, p2, q), -side * area(p2, p0, q)});
        if (added > best) {
            best = added;
            fourth = i;
        }
    }
    if (fourth == first) return 3;
    keep[3] = fourth;
    return 4;
}

void closestPointsOnSegments(glm::vec3 p1, glm::vec3 q1, glm::vec3 p2, glm::vec3 q2, glm::vec3& c1,
                             glm::vec3& c2) {
    constexpr float kEpsilon = 1e-12f;
    const glm::vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const float a = glm::dot(d1, d1), e = glm::dot(d2, d2), f = glm::dot(d2, r);
    float s = 0.0f, t = 0.0f;
    if (a <= kEpsilon && e <= kEpsilon) {
        s = t = 0.0f;
    } else if (a <= kEpsilon) {
        t = std::clamp(f / e, 0.0f, 1.0f);
    } else {
        const float c = glm::dot(d1, r);
        if (e <= kEpsilon) {
            s = std::clamp(-c / a, 0.0f, 1.0f);
        } else {
            // Closest points of the infinite lines, then clamped to each segment in turn.
            const float b = glm::dot(d1, d2), denom = a * e - b * b;
            s = denom > 0.0f ? std::clamp((b * f - c * e) / denom, 0.0f, 1.0f) : 0.0f;
            t = (b * s + f) / e;
            if (t < 0.0f) {
                t = 0.0f;
                s = std::clamp(-c / a, 0.0f, 1.0f);
            } else if (t > 1.0f) {
                t = 1.0f;
                s = std::clamp((b - c) / a, 0.0f, 1.0f);
            }
        }
    }
    c1 = p1 + d1 * s;
    c2 = p2 + d2 * t;
}

} // namespace rubble
