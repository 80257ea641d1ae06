// include/rubble/shared/layout.h: every shared struct and field, listed once, so that
// kernels/layout.cl and tests/gpu/layout_test.cpp measure the same sizes and offsets.
#pragma once

#include "rubble/shared/body.h"
#include "rubble/shared/broad_phase.h"
#include "rubble/shared/contact_row.h"
#include "rubble/shared/hull_contact.h"
#include "rubble/shared/lcp.h"
#include "rubble/shared/level_contact.h"
#include "rubble/shared/obstacle.h"
#include "rubble/shared/particle.h"
#include "rubble/shared/pgs_row.h"

// X(struct) names a struct's size; F(struct, field) a field's byte offset. In this order.
#define RUBBLE_SHARED_LAYOUT(X, F)                                                                                                              \
    X(Mat3)                                                                                                                                     \
    F(Mat3, r0) F(Mat3, r1) F(Mat3, r2) X(BodyPose) F(BodyPose, position) F(                                                                    \
        BodyPose, orientation) X(BodyVelocity) F(BodyVelocity,                                                                                  \
                                                 linear) F(BodyVelocity,                                                                        \
                                                           angular) X(BodyMomentum) F(BodyMomentum,                                             \
                                                                                      linear) F(BodyMomentum,                                   \
                                                                                                angular) X(BodyForce) F(BodyForce, force)       \
        F(BodyForce, torque) X(BodyMass) F(BodyMass, inertiaBody) F(BodyMass, inverseInertiaBody) F(BodyMass, mass) F(BodyMass, inverseMass) F( \
            BodyMass,                                                                                                                           \
            flags) F(BodyMass,                                                                                                                  \
                     pad0) X(Particle) F(Particle,                                                                                              \
                                         offset) F(Particle,                                                                                    \
                                                   body) F(Particle,                                                                            \
                                                           pad0) F(Particle,                                                                    \
                                                                   pad2) X(StaticShape) F(StaticShape,                                          \
                                                                                          normal)                                               \
            F(StaticShape, position) F(StaticShape, orientation) F(StaticShape, halfExtents) F(StaticShape, kind) F(StaticShape, friction) F(   \
                StaticShape,                                                                                                                    \
                restitution) F(StaticShape,                                                                                                     \
                               body) X(ParticleContact) F(ParticleContact, point)                                                               \
                F(ParticleContact, normal) F(ParticleContact, a) F(ParticleContact, b) F(                                                       \
                    ParticleContact,                                                                                                            \
                    particleA) F(ParticleContact,                                                                                               \
                                 featureB) X(ContactRow) F(ContactRow,                                                                          \
                                                           normal) F(ContactRow,                                                                \
                                                                     tangent1) F(ContactRow,                                                    \
                                                                                 tangent2) F(ContactRow,                                        \
                                                                                             rA) F(ContactRow,                                  \
                                                                                                   rB)                                          \
                    F(ContactRow, lambda) F(ContactRow, mass) F(ContactRow, a) F(                                                               \
                        ContactRow,                                                                                                             \
                        b) F(ContactRow,                                                                                                        \
                             bias) F(ContactRow,                                                                                                \
                                     friction) X(SolverParams) F(SolverParams,                                                                  \
                                                                 baumgarte) F(SolverParams, slop)                                               \
                        F(SolverParams, inverseDt) F(SolverParams, relaxation) X(                                                               \
                            ObstacleState) F(ObstacleState,                                                                                     \
                                             pose) F(ObstacleState, velocity)                                                                   \
                            F(ObstacleState, body) F(ObstacleState, flags) F(ObstacleState, pad1) X(                                            \
                                BodyImpulse) F(BodyImpulse,                                                                                     \
                                               linear) F(BodyImpulse, angular)                                                                  \
                                X(JacobiBody) F(JacobiBody, inverseInertiaWorld) X(LcpRow) F(                                                   \
                                    LcpRow,                                                                                                     \
                                    direction) F(LcpRow,                                                                                        \
                                                 armA) F(LcpRow,                                                                                \
                                                         armB) F(LcpRow, turnA)                                                                 \
                                    F(LcpRow, turnB) F(LcpRow, a) F(LcpRow, b) F(LcpRow, pad1) X(                                               \
                                        HullShape) F(HullShape,                                                                                 \
                                                     boundsMin) F(HullShape, boundsMax)                                                         \
                                        F(HullShape, centroid) F(HullShape, plane) F(HullShape, kind) F(                                        \
                                            HullShape, radius) F(HullShape,                                                                     \
                                                                 boundingRadius) F(HullShape, vertexStart)                                      \
                                            F(HullShape, vertexCount) F(HullShape, halfEdgeStart) F(                                            \
                                                HullShape,                                                                                      \
                                                edgeStart) F(HullShape,                                                                         \
                                                             edgeCount) F(HullShape, faceStart)                                                 \
                                                F(HullShape,                                                                                    \
                                                  faceCount) F(HullShape, halfHeight) F(HullShape,                                                                       \
                                                               pad1) X(HullHalfEdge) F(HullHalfEdge,                                            \
                                                                                       origin) F(HullHalfEdge,                                  \
                                                                                                 face) F(HullHalfEdge,                          \
                                                                                                         next)                                  \
                                                    F(HullHalfEdge, twin) X(HullEdge) F(HullEdge, origin) F(                                    \
                                                        HullEdge,                                                                               \
                                                        direction) F(HullEdge,                                                                  \
                                                                     normalLeft) F(HullEdge,                                                    \
                                                                                   normalRight) F(HullEdge, arc)                                \
                                                        X(RigidTransform) F(RigidTransform, rotation) F(                                        \
                                                            RigidTransform,                                                                     \
                                                            translation) X(SatHint) F(SatHint, feature)                                         \
                                                            F(SatHint, indexA) F(SatHint, indexB) F(SatHint, vertex) X(                         \
                                                                PairCache) F(PairCache,                                                         \
                                                                             reference) F(PairCache, feature)                                   \
                                                                F(PairCache, reusable) F(PairCache, pad2) X(                                    \
                                                                    ContactManifold) F(ContactManifold,                                         \
                                                                                       normal) F(ContactManifold, points)                       \
                                                                    F(ContactManifold, features) F(ContactManifold, a) F(                       \
                                                                        ContactManifold,                                                        \
                                                                        b) F(ContactManifold,                                                   \
                                                                             count) F(ContactManifold, pad0)                                    \
                                                                        X(BodyBox) F(BodyBox, min) F(BodyBox, max) X(BodyPairRecord) F(         \
                                                                            BodyPairRecord,                                                     \
                                                                            a) F(BodyPairRecord,                                                \
                                                                                 b) X(GridParams) F(GridParams, origin)                         \
                                                                            F(GridParams, inverseCell) F(                                       \
                                                                                GridParams,                                                     \
                                                                                cells) F(GridParams,                                            \
                                                                                         largeAbove) F(GridParams, sweepAxis)                   \
                                                                                F(GridParams, sweepBits) F(GridParams, pad0)                    \
                                                                                X(GridPartial)                     \
                                                                                F(GridPartial, lo) F(GridPartial, hi) F(                        \
                                                                                    GridPartial,                                                \
                                                                                    widthSum) F(GridPartial, count)                             \
                                                                                    F(GridPartial, pad2) X(PgsNormalRow) F(                     \
                                                                                        PgsNormalRow,                                           \
                                                                                        normal) F(PgsNormalRow, crossA)                         \
                                                                                        F(PgsNormalRow,                                         \
                                                                                          turnB) F(PgsNormalRow,                                \
                                                                                                   speeds) F(PgsNormalRow,                      \
                                                                                                             mass)                              \
                                                                                            X(PgsFrictionRows) F(                               \
                                                                                                PgsFrictionRows,                                \
                                                                                                tangent) F(PgsFrictionRows,                     \
                                                                                                           crossA)                              \
                                                                                                F(PgsFrictionRows,                              \
                                                                                                  turnB) F(PgsFrictionRows,                     \
                                                                                                           mass) F(PgsFrictionRows,             \
                                                                                                                   inverseMass)                 \
                                                                                                    X(PgsImpulse) F(                            \
                                                                                                        PgsImpulse,                             \
                                                                                                        pointInA)                               \
                                                                                                        F(PgsImpulse,                           \
                                                                                                          friction)                             \
                                                                                                            F(PgsImpulse,                       \
                                                                                                              normal)                           \
                                                                                                                F(PgsImpulse,                   \
                                                                                                                  feature)                      \
                                                                                                                    F(PgsImpulse,               \
                                                                                                                      pad1) \
    X(MeshTriangle) F(MeshTriangle, v) F(MeshTriangle, normal) F(MeshTriangle, neighbourNormal)     \
    F(MeshTriangle, edges) F(MeshTriangle, index) F(MeshTriangle, pad0) F(MeshTriangle, pad1)       \
    X(LevelNode) F(LevelNode, boxMin) F(LevelNode, boxMax) F(LevelNode, first) F(LevelNode, count)  \
    F(LevelNode, second) F(LevelNode, pad0) X(LevelShape) F(LevelShape, nodeStart)                   \
    F(LevelShape, nodeCount) F(LevelShape, triangleStart) F(LevelShape, triangleCount)
