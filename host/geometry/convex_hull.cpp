// host/geometry/convex_hull.cpp: Qhull's reentrant C library wrapped into ConvexPolygons.
#include "host/geometry/convex_hull.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <set>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

#include "host/core/math.h"

namespace rubble {

std::vector<glm::uvec3> ConvexPolygons::triangles() const {
    std::vector<glm::uvec3> out;
    for (const auto& f : faces)
        for (std::size_t i = 1; i + 1 < f.size(); ++i) out.emplace_back(f[0], f[i], f[i + 1]);
    return out;
}

namespace {

// Qhull prints its diagnostics to a FILE; this one collects them in memory for the error text.
class MessageBuffer {
  public:
    MessageBuffer() : file_(open_memstream(&data_, &size_)) {}
    ~MessageBuffer() {
        if (file_) std::fclose(file_);
        std::free(data_);
    }
    MessageBuffer(const MessageBuffer&) = delete;
    MessageBuffer& operator=(const MessageBuffer&) = delete;
    FILE* file() { return file_; }
    // The first line of what Qhull said, which names the problem.
    std::string firstLine() {
        std::fflush(file_);
        if (!data_) return {};
        std::string s(data_, size_);
        const auto start = s.find_first_not_of(" \n");
        if (start == std::string::npos) return {};
        const auto end = s.find('\n', start);
        return s.substr(start, end == std::string::npos ? std::string::npos : end - start);
    }

  private:
    char* data_ = nullptr;
    std::size_t size_ = 0;
    FILE* file_;
};

// Orders a convex facet's vertices counter-clockwise about its outward normal.
void orderAroundNormal(std::vector<std::uint32_t>& face, const std::vector<glm::vec3>& vertices,
                       glm::dvec3 normal) {
    glm::dvec3 centre(0.0);
    for (std::uint32_t v : face) centre += glm::dvec3(vertices[v]);
    centre /= double(face.size());
    const glm::dvec3 u = glm::normalize(glm::dvec3(vertices[face[0]]) - centre);
    const glm::dvec3 w = glm::cross(normal, u);
    auto angle = [&](std::uint32_t v) {
        const glm::dvec3 d = glm::dvec3(vertices[v]) - centre;
        return std::atan2(glm::dot(d, w), glm::dot(d, u));
    };
    std::sort(face.begin(), face.end(),
              [&](std::uint32_t a, std::uint32_t b) { return angle(a) < angle(b); });
}

} // namespace

Result<ConvexPolygons> computeConvexHull(std::span<const glm::vec3> points,
                                         const std::string& where) {
    if (points.size() < 4)
        return makeError(ErrorKind::BadInput, where,
                         "a convex hull needs at least 4 points that are not coplanar, got " +
                             std::to_string(points.size()));
    std::vector<coordT> coords;
    coords.reserve(points.size() * 3);
    for (std::size_t i = 0; i < points.size(); ++i) {
        if (!isFinite(points[i]))
            return makeError(ErrorKind::BadInput, where,
                             "point " + std::to_string(i) + " is not a finite number");
        coords.insert(coords.end(), {points[i].x, points[i].y, points[i].z});
    }

    MessageBuffer messages;
    qhT qhData;
    qhT* qh = &qhData;
    qh_zero(qh, messages.file());
    char flags[] = "qhull Qt";
    const int exitCode = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, flags,
                                      nullptr, messages.file());
    ConvexPolygons hull;
    std::string failure;
    if (exitCode != 0) {
        failure = messages.firstLine();
    } else {
        // Qt triangulates merged facets; triangles of one merged facet share its normal, so
        // gathering them by facet normal rebuilds the polygon.
        // Each face lists its vertices in the order they first appear; `inFace` makes that
        // O(log n) a vertex, so that a facet of many triangles costs no more than its corners.
        std::map<int, std::uint32_t> vertexIndex;
        std::map<std::array<double, 4>, std::vector<std::uint32_t>> facesByPlane;
        std::set<std::pair<const std::vector<std::uint32_t>*, std::uint32_t>> inFace;
        facetT* facet;
        FORALLfacets {
            const std::array<double, 4> plane{facet->normal[0], facet->normal[1],
                                              facet->normal[2], facet->offset};
            auto& face = facesByPlane[plane];
            vertexT *vertex, **vertexp;
            FOREACHvertex_(facet->vertices) {
                const int id = qh_pointid(qh, vertex->point);
                auto [it, added] = vertexIndex.try_emplace(id, std::uint32_t(hull.vertices.size()));
                if (added) hull.vertices.push_back(points[std::size_t(id)]);
                if (inFace.emplace(&face, it->second).second) face.push_back(it->second);
            }
        }
        for (auto& [plane, face] : facesByPlane) {
            orderAroundNormal(face, hull.vertices, glm::dvec3(plane[0], plane[1], plane[2]));
            hull.faces.push_back(std::move(face));
        }
    }
    qh_freeqhull(qh, !qh_ALL);
    int curLong = 0, totLong = 0;
    qh_memfreeshort(qh, &curLong, &totLong);

    if (exitCode != 0)
        return makeError(ErrorKind::BadInput, where,
                         "the points do not span a volume (coplanar or collinear); Qhull says: " +
                             failure);
    return hull;
}

} // namespace rubble
