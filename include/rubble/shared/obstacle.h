// include/rubble/shared/obstacle.h: a body the host steps (a CPU body next to device debris) as
// the device sees it each step: where it is, how fast it moves, whether it is near anything
// (stage placeObstacles, kernels/obstacles.cl; the host fills them in host/world/offload.cpp).
#pragma once

#include "rubble/shared/body.h"

RUBBLE_SHARED_BEGIN

// 80 bytes, uploaded every step for every obstacle.
typedef struct ObstacleState {
    BodyPose pose;         // at the start of the step
    BodyVelocity velocity; // at the start of the step; the debris' rows see it as fixed
    uint body;             // its index in the device's body arrays
    uint flags;            // RUBBLE_BODY_KINEMATIC, with RUBBLE_BODY_ABSENT when far from debris
    uint pad0, pad1;
} ObstacleState;
RUBBLE_STATIC_ASSERT_SIZE(ObstacleState, 80);

RUBBLE_SHARED_END
