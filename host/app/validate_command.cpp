// host/app/validate_command.cpp: `rubble validate SCENE`: load, build, summarise.
#include <cstdio>
#include <map>
#include <string>

#include "host/app/commands.h"
#include "rubble/world.h"

namespace rubble::app {
namespace {

const char* shapeTypeName(ShapeType t) {
    switch (t) {
    case ShapeType::Box: return "box";
    case ShapeType::Sphere: return "sphere";
    case ShapeType::Convex: return "convex";
    case ShapeType::Mesh: return "mesh";
    case ShapeType::Plane: return "plane";
    case ShapeType::Capsule: return "capsule";
    }
    return "?";
}

} // namespace

int validateCommand(const ValidateArgs& args) {
    Result<Scene> scene = loadScene(args.scene);
    if (!scene) return report(scene.error());
    Result<World> world = World::create(*scene);
    if (!world) return report(world.error());
    reportWarnings(*world);

    std::size_t statics = 0, kinematic = 0;
    double totalMass = 0.0;
    for (std::uint32_t i = 0; i < world->bodyCount(); ++i) {
        const BodyState b = world->body(i);
        statics += b.isStatic && !b.isKinematic ? 1 : 0;
        kinematic += b.isKinematic ? 1 : 0;
        totalMass += b.mass;
    }
    std::printf("scene %s (%s): valid\n", scene->name.c_str(), args.scene.c_str());
    const std::string kinematicText =
        kinematic ? std::to_string(kinematic) + " kinematic, " : std::string();
    std::printf("bodies: %u (%zu static, %s%zu dynamic), total mass %.6g kg\n",
                world->bodyCount(), statics, kinematicText.c_str(),
                world->bodyCount() - statics - kinematic, totalMass);
    std::printf("shapes: %zu", scene->shapes.size());
    for (std::size_t i = 0; i < scene->shapes.size(); ++i) {
        const ShapeDesc& d = scene->shapes[i];
        // Level geometry: its grid and triangles.
        std::string detail = shapeTypeName(d.type);
        if (d.heightField)
            detail = "heightfield " + std::to_string(d.heightField->columns) + " x " +
                     std::to_string(d.heightField->rows) + ", " +
                     std::to_string(d.triangles.size()) + " triangles";
        else if (d.type == ShapeType::Mesh)
            detail += ", " + std::to_string(d.triangles.size()) + " triangles";
        std::printf("%s%s (%s)", i ? ", " : ": ", d.name.c_str(), detail.c_str());
    }
    std::printf("\n");
    std::size_t balls = 0;
    for (const JointDesc& j : scene->joints) balls += j.type == JointType::Ball ? 1 : 0;
    std::printf("joints: %zu (%zu ball, %zu hinge)\n", scene->joints.size(), balls,
                scene->joints.size() - balls);
    std::printf("simulation: dt %.6g s, %d steps, %s integrator, %s backend, %s collision, %s "
                "solver (%d iterations)\n",
                double(scene->simulation.dt), scene->simulation.steps,
                std::string(toString(scene->simulation.integrator)).c_str(),
                std::string(toString(scene->simulation.backend)).c_str(),
                std::string(toString(scene->simulation.collisionMethod())).c_str(),
                std::string(toString(scene->simulation.solverType())).c_str(),
                scene->simulation.solver.iterations);
    return kExitOk;
}

} // namespace rubble::app
