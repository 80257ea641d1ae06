// host/io/quality.h: how physically right a run's end state is, judged the same way for rubble
// and for the peer engines of the benchmarks: bodies sunk through static planes, how deep any
// body reaches below them, how much the bodies still move, and their kinetic energy.
#pragma once

#include <span>
#include <vector>

#include "host/io/trajectory_writer.h"
#include "rubble/shape.h"

namespace rubble {

/// What the assessment needs of one body.
struct QualityBody {
    const ShapeGeometry* shape = nullptr;
    double mass = 0.0;         ///< kg; 0 for static bodies
    glm::dmat3 inertia{0.0};   ///< body frame, about the centre of mass, kg m^2
    bool isStatic = false;
};

/// The figures, over dynamic bodies.
struct QualityReport {
    std::size_t sunk = 0;           ///< centre of mass below a static plane
    double floorPenetration = 0.0;  ///< deepest point of any body below a static plane, m
    double meanDrift = 0.0;         ///< mean speed of the centres over the interval, m/s
    double kineticEnergy = 0.0;     ///< J, at the end
    double maxSpeed = 0.0;          ///< m/s, at the end
    std::size_t moving = 0;         ///< bodies faster than kMovingSpeed at the end
};

/// A body still moving at the end of a run: its centre faster than this, m/s.
inline constexpr double kMovingSpeed = 0.5;

/// Assesses `now` (one row per body, in the same order as `bodies`) against `before`, taken
/// `interval` seconds earlier (the drift is 0 when `before` is empty).
QualityReport assessQuality(std::span<const QualityBody> bodies,
                            std::span<const TrajectoryRow> now,
                            std::span<const TrajectoryRow> before, double interval);

} // namespace rubble
