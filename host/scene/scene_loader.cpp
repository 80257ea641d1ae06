// host/scene/scene_loader.cpp: scene files (SCENE_FORMAT.md, version 1) into a checked Scene.
// Every error names the file and the JSON path of the field; nothing falls back silently.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "host/scene/ragdoll.h"
#include "host/scene/generators.h"
#include "host/scene/height_field.h"
#include "host/scene/json_reader.h"
#include "host/geometry/obj_mesh.h"
#include "rubble/scene.h"

namespace rubble {

std::optional<std::uint32_t> Scene::findBody(std::string_view bodyName) const {
    for (std::size_t i = 0; i < bodies.size(); ++i)
        if (bodies[i].name == bodyName) return std::uint32_t(i);
    return std::nullopt;
}

namespace {

constexpr std::int64_t kMaxGridCount = 1'000'000;
constexpr float kMinQuatNorm = 1e-6f;
// A ragdoll from 18 cm to 180 m tall: its thinnest part stays within kMinLength..kMaxLength.
constexpr double kMinRagdollScale = 0.1;
constexpr double kMaxRagdollScale = 100.0;

class SceneLoader {
  public:
    SceneLoader(const std::string& file, std::string baseDir)
        : file_(file), baseDir_(std::move(baseDir)) {}

    Result<Scene> load(const Json& root) {
        ObjectReader top(root, "", file_);
        RUBBLE_TRY(top.checkIsObject());
        RUBBLE_TRY(top.checkKeys(std::span<const std::string_view>(kSceneKeys)));
        RUBBLE_TRY(readHeader(top));
        if (top.has("simulation")) RUBBLE_TRY(readSimulation(ObjectReader(top.at("simulation"), "simulation", file_)));
        RUBBLE_TRY(readMaterials(top));
        RUBBLE_TRY(readShapes(top));
        RUBBLE_TRY(readBodies(top));
        RUBBLE_TRY(readGenerators(top));
        RUBBLE_TRY(readJoints(top));
        RUBBLE_TRY(readEvents(top));
        return std::move(scene_);
    }

  private:
    Status readHeader(const ObjectReader& top) {
        RUBBLE_TRY(top.require("format"));
        std::string format;
        RUBBLE_TRY(top.read("format", format));
        if (format != "rubble-scene")
            return top.fail("format", "expected \"rubble-scene\", got \"" + format + "\"");
        RUBBLE_TRY(top.require("version"));
        std::int64_t version = 0;
        RUBBLE_TRY(top.read("version", version, 0, std::numeric_limits<std::int64_t>::max()));
        if (version != 1)
            return top.fail("version", "unsupported version " + std::to_string(version) +
                                           " (this rubble reads version 1)");
        scene_.file = file_;
        scene_.name = std::filesystem::path(file_).stem().string();
        return top.read("name", scene_.name);
    }

    // Every key of `simulation` is an option of the table (host/core/option_table.h); a group
    // (`collision`, `solver`) is an object holding the options whose key starts with it.
    Status readSimulation(const ObjectReader& r, const std::string& group = "") {
        RUBBLE_TRY(r.checkIsObject());
        std::vector<std::string_view> keys; // this object's keys, in the table's order
        for (const Option& o : optionTable()) {
            if (o.scope != OptionScope::Simulation || !o.key.starts_with(group)) continue;
            const std::string_view rest = o.key.substr(group.size());
            const std::string_view key = rest.substr(0, rest.find('.'));
            if (std::find(keys.begin(), keys.end(), key) == keys.end()) keys.push_back(key);
        }
        RUBBLE_TRY(r.checkKeys(keys));
        for (std::string_view key : keys) {
            if (!r.has(key)) continue;
            const std::string path = group + std::string(key);
            if (const Option* o = findOptionByKey(path))
                RUBBLE_TRY(r.readOption(key, *o, OptionTarget{&scene_.simulation, nullptr}));
            else
                RUBBLE_TRY(readSimulation(ObjectReader(r.at(key), r.pathOf(key), file_),
                                          path + "."));
        }
        return {};
    }

    Status readMaterials(const ObjectReader& top) {
        scene_.materials.push_back(MaterialDesc{"default", 0.5f, 0.0f});
        if (!top.has("materials")) return {};
        ObjectReader all(top.at("materials"), "materials", file_);
        RUBBLE_TRY(all.checkIsObject());
        for (const auto& [name, value] : top.at("materials").items()) {
            ObjectReader m(value, all.pathOf(name), file_);
            RUBBLE_TRY(m.checkIsObject());
            RUBBLE_TRY(m.checkKeys({"friction", "restitution"}));
            MaterialDesc desc{name, 0.5f, 0.0f};
            RUBBLE_TRY(m.read("friction", desc.friction, Range::NonNegative));
            RUBBLE_TRY(m.read("restitution", desc.restitution, Range::UnitInterval));
            if (name == "default")
                scene_.materials[0] = desc;
            else
                scene_.materials.push_back(desc);
        }
        return {};
    }

    Status readShapes(const ObjectReader& top) {
        if (!top.has("shapes")) return {};
        ObjectReader all(top.at("shapes"), "shapes", file_);
        RUBBLE_TRY(all.checkIsObject());
        for (const auto& [name, value] : top.at("shapes").items()) {
            ObjectReader s(value, all.pathOf(name), file_);
            RUBBLE_TRY(s.checkIsObject());
            RUBBLE_TRY(s.require("type"));
            ShapeDesc d;
            d.name = name;
            d.where = s.where();
            std::string type;
            RUBBLE_TRY(s.read("type", type));
            if (type == "box") {
                d.type = ShapeType::Box;
                RUBBLE_TRY(s.checkKeys({"type", "half_extents"}));
                RUBBLE_TRY(s.require("half_extents"));
                RUBBLE_TRY(s.read("half_extents", d.halfExtents, Range::Length));
            } else if (type == "sphere") {
                d.type = ShapeType::Sphere;
                RUBBLE_TRY(s.checkKeys({"type", "radius"}));
                RUBBLE_TRY(s.require("radius"));
                RUBBLE_TRY(s.read("radius", d.radius, Range::Length));
            } else if (type == "capsule") {
                d.type = ShapeType::Capsule;
                RUBBLE_TRY(s.checkKeys({"type", "radius", "half_height"}));
                RUBBLE_TRY(s.require("radius"));
                RUBBLE_TRY(s.require("half_height"));
                RUBBLE_TRY(s.read("radius", d.radius, Range::Length));
                RUBBLE_TRY(s.read("half_height", d.halfHeight, Range::NonNegative));
                if (d.halfHeight > float(kMaxLength))
                    return s.fail("half_height", "must be at most " + lengthText(kMaxLength) +
                                                     " m, got " + std::to_string(d.halfHeight));
            } else if (type == "convex") {
                d.type = ShapeType::Convex;
                RUBBLE_TRY(s.checkKeys({"type", "vertices"}));
                RUBBLE_TRY(readPoints(s, "vertices", d.points));
                RUBBLE_TRY(checkExtent(d.points, s.where("vertices"), "vertices"));
            } else if (type == "mesh") {
                d.type = ShapeType::Mesh;
                RUBBLE_TRY(s.checkKeys({"type", "file", "scale"}));
                RUBBLE_TRY(s.require("file"));
                RUBBLE_TRY(s.read("file", d.file));
                RUBBLE_TRY(s.read("scale", d.scale, Range::Positive));
                d.file = (std::filesystem::path(baseDir_) / d.file).lexically_normal().string();
                Result<TriangleMesh> mesh = loadObjMesh(d.file, d.scale, s.where("file"));
                RUBBLE_TRY(mesh);
                RUBBLE_TRY(checkExtent(mesh->vertices, s.where("scale"), d.file));
                d.points = std::move(mesh->vertices);
                d.triangles = std::move(mesh->triangles);
            } else if (type == "heightfield") {
                RUBBLE_TRY(s.checkKeys({"type", "heights", "spacing", "file", "height_scale"}));
                RUBBLE_TRY(readHeightField(s, baseDir_, d));
            } else if (type == "plane") {
                d.type = ShapeType::Plane;
                RUBBLE_TRY(s.checkKeys({"type", "normal", "offset"}));
                RUBBLE_TRY(s.readDirection("normal", d.normal));
                RUBBLE_TRY(s.read("offset", d.offset));
            } else {
                return s.fail("type", "unknown shape type \"" + type +
                                          "\" (expected box, sphere, capsule, convex, mesh, heightfield or plane)");
            }
            shapeIndex_[name] = std::uint32_t(scene_.shapes.size());
            scene_.shapes.push_back(std::move(d));
        }
        return {};
    }

    Status readPoints(const ObjectReader& s, std::string_view key, std::vector<glm::vec3>& out) {
        RUBBLE_TRY(s.require(key));
        const Json& v = s.at(key);
        if (!v.is_array()) return s.fail(key, "expected an array of [x, y, z] points, got " + brief(v));
        if (v.size() > kMaxMeshVertices)
            return s.fail(key, "has " + std::to_string(v.size()) + " points, more than the " +
                                   std::to_string(kMaxMeshVertices) +
                                   " rubble builds a shape from");
        for (std::size_t i = 0; i < v.size(); ++i) {
            Result<glm::vec3> p = vec3FromJson(v[i], s.where(key) + indexPath(i));
            RUBBLE_TRY(p);
            out.push_back(*p);
        }
        return {};
    }

    // The points of a convex or mesh shape (after its scale) lie within kMaxLength of the
    // shape's origin and span at least kMinLength: the range of a box's sizes.
    static Status checkExtent(const std::vector<glm::vec3>& points, const std::string& where,
                              const std::string& what) {
        glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
        for (const glm::vec3& p : points) {
            if (!(glm::all(glm::lessThanEqual(glm::abs(p), glm::vec3(float(kMaxLength))))))
                return makeError(ErrorKind::BadInput, where,
                                 "a point of " + what + " lies farther than " +
                                     lengthText(kMaxLength) + " m from the shape's origin");
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
        const glm::vec3 extent = hi - lo;
        if (!points.empty() && std::max({extent.x, extent.y, extent.z}) < float(kMinLength))
            return makeError(ErrorKind::BadInput, where,
                             "the points of " + what + " span less than " +
                                 lengthText(kMinLength) + " m");
        return {};
    }

    Status lookupShape(const ObjectReader& r, std::uint32_t& out) {
        RUBBLE_TRY(r.require("shape"));
        std::string name;
        RUBBLE_TRY(r.read("shape", name));
        const auto it = shapeIndex_.find(name);
        if (it == shapeIndex_.end()) return r.fail("shape", "no shape named \"" + name + "\" in shapes");
        out = it->second;
        return {};
    }

    Status lookupMaterial(const ObjectReader& r, std::uint32_t& out) {
        if (!r.has("material")) return {};
        std::string name;
        RUBBLE_TRY(r.read("material", name));
        for (std::size_t i = 0; i < scene_.materials.size(); ++i)
            if (scene_.materials[i].name == name) {
                out = std::uint32_t(i);
                return {};
            }
        return r.fail("material", "no material named \"" + name + "\" in materials");
    }

    // mass, density and static, shared by bodies and generators.
    Status readMassFields(const ObjectReader& r, BodyDesc& b) {
        RUBBLE_TRY(r.read("static", b.isStatic));
        if (r.has("mass")) {
            float m = 0.0f;
            RUBBLE_TRY(r.read("mass", m, Range::Positive));
            b.mass = m;
        }
        if (r.has("density")) {
            float d = 0.0f;
            RUBBLE_TRY(r.read("density", d, Range::Positive));
            b.density = d;
        }
        const ShapeDesc& shape = scene_.shapes[b.shape];
        if (b.isKinematic) {
            if (b.isStatic)
                return r.fail("kinematic", "a body is static or kinematic, not both");
            if (b.mass || b.density)
                return r.fail(b.mass ? "mass" : "density",
                              "a kinematic body has infinite mass (its velocities move it); "
                              "remove mass and density");
            if (shape.type == ShapeType::Plane || shape.heightField)
                return r.fail("shape", std::string(shape.heightField ? "heightfield" : "plane") +
                                           " shapes are for static bodies only");
            return {};
        }
        if (b.isStatic) {
            if (b.mass || b.density)
                return r.fail(b.mass ? "mass" : "density",
                              "a static body has infinite mass; remove mass and density");
            return {};
        }
        if (shape.type == ShapeType::Plane || shape.heightField)
            return r.fail("shape", std::string(shape.heightField ? "heightfield" : "plane") +
                                       " shapes are for static bodies only; add \"static\": true");
        if (b.mass && b.density) return r.fail("density", "give mass or density, not both");
        if (!b.mass && !b.density)
            return makeError(ErrorKind::BadInput, r.where(),
                             "a dynamic body needs \"mass\" or \"density\" (or \"static\": true)");
        return {};
    }

    Status addBody(BodyDesc b, const ObjectReader& r, std::string_view nameKey) {
        if (b.name.empty()) return r.fail(nameKey, "a body name must not be empty");
        if (!bodyNames_.emplace(b.name, b.where).second)
            return r.fail(nameKey, "duplicate body name \"" + b.name + "\" (first defined at " +
                                       bodyNames_[b.name] + ")");
        scene_.bodies.push_back(std::move(b));
        return {};
    }

    Status readBodies(const ObjectReader& top) {
        if (!top.has("bodies")) return {};
        const Json& list = top.at("bodies");
        if (!list.is_array()) return top.fail("bodies", "expected an array of bodies, got " + brief(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            ObjectReader r(list[i], "bodies[" + std::to_string(i) + "]", file_);
            RUBBLE_TRY(r.checkIsObject());
            RUBBLE_TRY(r.checkKeys({"name", "shape", "static", "kinematic", "mass", "density",
                                    "position", "orientation", "linear_velocity",
                                    "angular_velocity", "material", "debris"}));
            BodyDesc b;
            b.where = r.where();
            RUBBLE_TRY(r.require("name"));
            RUBBLE_TRY(r.read("name", b.name));
            RUBBLE_TRY(lookupShape(r, b.shape));
            RUBBLE_TRY(lookupMaterial(r, b.material));
            RUBBLE_TRY(r.read("kinematic", b.isKinematic));
            RUBBLE_TRY(readMassFields(r, b));
            RUBBLE_TRY(r.read("position", b.position));
            RUBBLE_TRY(r.readQuaternion("orientation", b.orientation));
            RUBBLE_TRY(r.read("linear_velocity", b.linearVelocity));
            RUBBLE_TRY(r.read("angular_velocity", b.angularVelocity));
            RUBBLE_TRY(r.read("debris", b.debris));
            if (b.isStatic && (glm::length(b.linearVelocity) > 0.0f || glm::length(b.angularVelocity) > 0.0f))
                return r.fail(r.has("linear_velocity") ? "linear_velocity" : "angular_velocity",
                              "a static body never moves; its velocity must be zero");
            RUBBLE_TRY(addBody(std::move(b), r, "name"));
        }
        return {};
    }

    Status readGenerators(const ObjectReader& top) {
        if (!top.has("generators")) return {};
        const Json& list = top.at("generators");
        if (!list.is_array())
            return top.fail("generators", "expected an array of generators, got " + brief(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            ObjectReader r(list[i], "generators[" + std::to_string(i) + "]", file_);
            RUBBLE_TRY(r.checkIsObject());
            RUBBLE_TRY(r.require("type"));
            std::string type;
            RUBBLE_TRY(r.read("type", type));
            if (type == "grid") {
                RUBBLE_TRY(readGrid(r, i));
            } else if (type == "ragdoll") {
                RUBBLE_TRY(readRagdoll(r, i));
            } else {
                return r.fail("type", "unknown generator type \"" + type + "\" (expected grid or ragdoll)");
            }
        }
        return {};
    }

    Status readGrid(const ObjectReader& r, std::size_t index) {
        RUBBLE_TRY(r.checkKeys({"type", "shape", "mass", "density", "static", "material", "count",
                                "origin", "spacing", "rotation_jitter", "seed", "name_prefix",
                                "debris", "linear_velocity", "angular_velocity"}));
        BodyDesc proto;
        RUBBLE_TRY(lookupShape(r, proto.shape));
        RUBBLE_TRY(lookupMaterial(r, proto.material));
        RUBBLE_TRY(readMassFields(r, proto));
        RUBBLE_TRY(r.read("debris", proto.debris));
        RUBBLE_TRY(r.read("linear_velocity", proto.linearVelocity));
        RUBBLE_TRY(r.read("angular_velocity", proto.angularVelocity));
        RUBBLE_TRY(r.require("count"));
        const Json& c = r.at("count");
        if (!c.is_array() || c.size() != 3)
            return r.fail("count", "expected an array of 3 integers, got " + brief(c));
        glm::ivec3 count(1);
        for (int k = 0; k < 3; ++k) {
            if (!c[std::size_t(k)].is_number_integer() || c[std::size_t(k)].get<std::int64_t>() < 1 ||
                c[std::size_t(k)].get<std::int64_t>() > kMaxGridCount)
                return r.fail("count", "each count must be an integer from 1 to " +
                                           std::to_string(kMaxGridCount) + ", got " + brief(c));
            count[k] = int(c[std::size_t(k)].get<std::int64_t>());
        }
        const std::int64_t total = std::int64_t(count.x) * count.y * count.z;
        if (total > kMaxGridCount)
            return r.fail("count", "a grid of " + std::to_string(total) + " bodies is more than " +
                                       std::to_string(kMaxGridCount));
        glm::vec3 origin(0.0f), spacing(1.0f);
        float jitter = 0.0f;
        std::int64_t seed = 0;
        std::string prefix = "g" + std::to_string(index) + "_";
        RUBBLE_TRY(r.read("origin", origin));
        RUBBLE_TRY(r.read("spacing", spacing));
        RUBBLE_TRY(r.read("rotation_jitter", jitter, Range::NonNegative));
        RUBBLE_TRY(r.read("seed", seed, 0, std::numeric_limits<std::uint32_t>::max()));
        RUBBLE_TRY(r.read("name_prefix", prefix));
        const std::vector<glm::vec3> positions = gridPositions(count, origin, spacing);
        const std::vector<glm::quat> rotations =
            jitterRotations(std::uint32_t(seed), positions.size(), jitter);
        for (std::size_t k = 0; k < positions.size(); ++k) {
            BodyDesc b = proto;
            b.name = prefix + std::to_string(k);
            b.where = r.where() + " (" + b.name + ")";
            b.position = positions[k];
            b.orientation = rotations[k];
            RUBBLE_TRY(addBody(std::move(b), r, "name_prefix"));
        }
        return {};
    }

    // The ten parts and nine joints of host/scene/ragdoll, offset into the scene's arrays.
    Status readRagdoll(const ObjectReader& r, std::size_t index) {
        RUBBLE_TRY(r.checkKeys({"type", "name_prefix", "position", "scale", "material", "debris"}));
        RagdollSpec spec;
        spec.prefix = "ragdoll" + std::to_string(index);
        spec.where = r.where();
        RUBBLE_TRY(r.read("name_prefix", spec.prefix));
        RUBBLE_TRY(r.read("position", spec.position));
        RUBBLE_TRY(r.read("scale", spec.scale, Range::Positive));
        if (!(spec.scale >= kMinRagdollScale && spec.scale <= kMaxRagdollScale))
            return r.fail("scale", "must be between " + lengthText(kMinRagdollScale) + " and " +
                                       lengthText(kMaxRagdollScale) + " (the ragdoll's parts are " +
                                       "sized from it), got " + brief(r.at("scale")));
        RUBBLE_TRY(lookupMaterial(r, spec.material));
        RUBBLE_TRY(r.read("debris", spec.debris));
        RagdollParts parts = buildRagdoll(spec);
        const auto firstShape = std::uint32_t(scene_.shapes.size());
        const auto firstBody = std::uint32_t(scene_.bodies.size());
        for (ShapeDesc& shape : parts.shapes) scene_.shapes.push_back(std::move(shape));
        for (BodyDesc& b : parts.bodies) {
            b.shape += firstShape;
            RUBBLE_TRY(addBody(std::move(b), r, "name_prefix"));
        }
        for (JointDesc& j : parts.joints) {
            j.a += firstBody;
            j.b += firstBody;
            scene_.joints.push_back(std::move(j));
        }
        return {};
    }

    Status lookupBody(const ObjectReader& r, std::string_view key, std::uint32_t& out) {
        RUBBLE_TRY(r.require(key));
        std::string name;
        RUBBLE_TRY(r.read(key, name));
        const std::optional<std::uint32_t> i = scene_.findBody(name);
        if (!i) return r.fail(key, "no body named \"" + name + "\"");
        out = *i;
        return {};
    }

    Status readJoints(const ObjectReader& top) {
        if (!top.has("joints")) return {};
        const Json& list = top.at("joints");
        if (!list.is_array()) return top.fail("joints", "expected an array of joints, got " + brief(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            ObjectReader r(list[i], "joints[" + std::to_string(i) + "]", file_);
            RUBBLE_TRY(r.checkIsObject());
            RUBBLE_TRY(r.require("type"));
            std::string type;
            RUBBLE_TRY(r.read("type", type));
            JointDesc j;
            j.where = r.where();
            if (type == "ball") {
                j.type = JointType::Ball;
                RUBBLE_TRY(r.checkKeys({"type", "a", "b", "anchor"}));
            } else if (type == "hinge") {
                j.type = JointType::Hinge;
                RUBBLE_TRY(r.checkKeys({"type", "a", "b", "anchor", "axis"}));
                RUBBLE_TRY(r.require("axis"));
                RUBBLE_TRY(r.readDirection("axis", j.axis));
            } else {
                return r.fail("type", "unknown joint type \"" + type + "\" (expected ball or hinge)");
            }
            RUBBLE_TRY(lookupBody(r, "a", j.a));
            RUBBLE_TRY(lookupBody(r, "b", j.b));
            if (j.a == j.b) return r.fail("b", "a joint needs two different bodies");
            if (scene_.bodies[j.a].isStatic && scene_.bodies[j.b].isStatic)
                return r.fail("b", "a joint between two static bodies does nothing");
            RUBBLE_TRY(r.require("anchor"));
            RUBBLE_TRY(r.read("anchor", j.anchor));
            scene_.joints.push_back(j);
        }
        return {};
    }

    Status readEvents(const ObjectReader& top) {
        if (!top.has("events")) return {};
        const Json& list = top.at("events");
        if (!list.is_array()) return top.fail("events", "expected an array of events, got " + brief(list));
        for (std::size_t i = 0; i < list.size(); ++i) {
            ObjectReader r(list[i], "events[" + std::to_string(i) + "]", file_);
            RUBBLE_TRY(r.checkIsObject());
            RUBBLE_TRY(r.require("type"));
            std::string type;
            RUBBLE_TRY(r.read("type", type));
            if (type != "explosion")
                return r.fail("type", "unknown event type \"" + type + "\" (expected explosion)");
            RUBBLE_TRY(r.checkKeys({"type", "time", "centre", "impulse", "radius"}));
            EventDesc e;
            e.where = r.where();
            for (const char* key : {"time", "centre", "impulse", "radius"}) RUBBLE_TRY(r.require(key));
            RUBBLE_TRY(r.read("time", e.time, Range::NonNegative));
            RUBBLE_TRY(r.read("centre", e.centre));
            RUBBLE_TRY(r.read("impulse", e.impulse, Range::NonNegative));
            RUBBLE_TRY(r.read("radius", e.radius, Range::Positive));
            scene_.events.push_back(e);
        }
        return {};
    }

    const std::string& file_;
    std::string baseDir_;
    Scene scene_;
    std::map<std::string, std::uint32_t> shapeIndex_;
    std::map<std::string, std::string> bodyNames_;
};

} // namespace

Result<Scene> parseScene(std::string_view text, const std::string& file, const std::string& baseDir) {
    Result<Json> root = parseJsonText(text, file);
    RUBBLE_TRY(root);
    SceneLoader loader(file, baseDir);
    return loader.load(*root);
}

Result<Scene> loadScene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::error_code ec;
        const bool exists = std::filesystem::exists(path, ec);
        return makeError(ErrorKind::BadInput, path,
                         exists ? "cannot read the scene file" : "scene file not found");
    }
    std::ostringstream text;
    text << in.rdbuf();
    const std::string base = std::filesystem::path(path).parent_path().string();
    return parseScene(text.str(), path, base.empty() ? "." : base);
}

} // namespace rubble
