// include/rubble/shared/events.h: scene events per element (stage applyForces): the radial
// impulse of an explosion on one body. The CPU path is host/dynamics/forces.cpp, the device's
// kernels/events.cl; both call this.
#pragma once

#include "rubble/shared/math.h"

RUBBLE_SHARED_BEGIN

// The impulse (N s, world, in xyz) an explosion at `centre` (m) of strength `impulse` (N s) and
// reach `radius` (m) gives a body whose centre of mass is at `position`: impulse (1 - d / radius)
// away from the centre when d < radius (straight up for a body at the centre). w is 1 when the
// body is within reach (it wakes), 0 when not (the impulse is then zero).
RUBBLE_FN float4 explosionImpulseItem(float4 position, float4 centre, float impulse,
                                      float radius) {
    const float4 offset = vec4(position.x - centre.x, position.y - centre.y,
                               position.z - centre.z);
    const float d = length3(offset);
    if (!(d < radius)) return make4(0.0f, 0.0f, 0.0f, 0.0f);
    const float4 away = d > 0.0f ? vec4(offset.x / d, offset.y / d, offset.z / d)
                                 : vec4(0.0f, 1.0f, 0.0f);
    const float magnitude = impulse * (1.0f - d / radius);
    return make4(away.x * magnitude, away.y * magnitude, away.z * magnitude, 1.0f);
}

RUBBLE_SHARED_END
