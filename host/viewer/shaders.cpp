// host/viewer/shaders.cpp: GLSL sources. Lighting is in linear RGB; the frame is written with a
// gamma of 2.2 applied at the end of each fragment shader.
#include "host/viewer/shaders.h"

namespace rubble::viewer::shaders {

const char* const kBodyVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 iPosition;
layout(location = 3) in vec4 iOrientation; // quaternion (x, y, z, w)
layout(location = 4) in vec4 iColour;
uniform mat4 uViewProjection;
out vec3 vWorld;
out vec3 vNormal;
out vec3 vColour;

vec3 rotate(vec4 q, vec3 v) {
    vec3 t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

void main() {
    vWorld = iPosition.xyz + rotate(iOrientation, aPosition);
    vNormal = rotate(iOrientation, aNormal);
    vColour = iColour.rgb;
    gl_Position = uViewProjection * vec4(vWorld, 1.0);
}
)";

const char* const kBodyFragment = R"(#version 330 core
in vec3 vWorld;
in vec3 vNormal;
in vec3 vColour;
uniform vec3 uEye;
uniform vec3 uLightDirection; // unit, towards the light
out vec4 fragColour;

void main() {
    vec3 n = normalize(vNormal);
    vec3 toEye = normalize(uEye - vWorld);
    if (dot(n, toEye) < 0.0) n = -n; // open meshes show their inside lit too
    float diffuse = max(dot(n, uLightDirection), 0.0);
    vec3 halfway = normalize(uLightDirection + toEye);
    float specular = diffuse > 0.0 ? pow(max(dot(n, halfway), 0.0), 48.0) : 0.0;
    float sky = 0.5 + 0.5 * n.y;
    vec3 ambient = mix(vec3(0.10, 0.09, 0.08), vec3(0.22, 0.24, 0.28), sky);
    vec3 linear = vColour * (ambient + 0.85 * diffuse) + vec3(0.25 * specular);
    fragColour = vec4(pow(linear, vec3(1.0 / 2.2)), 1.0);
}
)";

const char* const kGroundVertex = R"(#version 330 core
layout(location = 0) in vec2 aCorner; // in [-1, 1]^2
uniform vec3 uCentre;
uniform vec3 uAxisU; // unit, in the plane
uniform vec3 uAxisV; // unit, in the plane
uniform float uHalfSize;
uniform vec2 uGridOffset; // the centre's grid coordinates, m
uniform mat4 uViewProjection;
out vec2 vLocal;
out vec2 vGrid;

void main() {
    vLocal = uHalfSize * aCorner;
    vGrid = uGridOffset + vLocal;
    vec3 vWorld = uCentre + vLocal.x * uAxisU + vLocal.y * uAxisV;
    gl_Position = uViewProjection * vec4(vWorld, 1.0);
}
)";

const char* const kGroundFragment = R"(#version 330 core
in vec2 vLocal;
in vec2 vGrid;
uniform vec3 uNormal;
uniform vec3 uLightDirection;
uniform vec3 uBase;       // linear RGB of the ground
uniform vec3 uBackground; // linear RGB the ground fades into
uniform float uFadeStart; // m from the centre of the square
uniform float uFadeEnd;
out vec4 fragColour;

// Coverage of grid lines every `spacing` m, about one pixel wide at any distance.
float gridLines(vec2 p, float spacing) {
    vec2 q = p / spacing;
    vec2 width = fwidth(q);
    vec2 distance = abs(fract(q - 0.5) - 0.5) / max(width, vec2(1e-6));
    return 1.0 - min(min(distance.x, distance.y), 1.0);
}

void main() {
    float diffuse = max(dot(uNormal, uLightDirection), 0.0);
    vec3 colour = uBase * (0.35 + 0.65 * diffuse);
    colour = mix(colour, colour * 0.72, gridLines(vGrid, 1.0));
    colour = mix(colour, colour * 0.45, gridLines(vGrid, 10.0));
    float fade = smoothstep(uFadeStart, uFadeEnd, length(vLocal));
    fragColour = vec4(pow(mix(colour, uBackground, fade), vec3(1.0 / 2.2)), 1.0);
}
)";

const char* const kLineVertex = R"(#version 330 core
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProjection;
out vec4 vColour;

void main() {
    vColour = aColour;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
)";

const char* const kLineFragment = R"(#version 330 core
in vec4 vColour;
out vec4 fragColour;

void main() { fragColour = vec4(pow(vColour.rgb, vec3(1.0 / 2.2)), vColour.a); }
)";

const char* const kPointVertex = R"(#version 330 core
layout(location = 0) in vec4 aParticle; // xyz world, w radius
uniform mat4 uViewProjection;
uniform float uPixelsPerUnitAtOne; // projected size of 1 m at a depth of 1 m, px

void main() {
    gl_Position = uViewProjection * vec4(aParticle.xyz, 1.0);
    gl_PointSize = max(2.0 * aParticle.w * uPixelsPerUnitAtOne / max(gl_Position.w, 1e-3), 1.0);
}
)";

const char* const kPointFragment = R"(#version 330 core
uniform vec3 uColour;
out vec4 fragColour;

void main() {
    vec2 p = 2.0 * gl_PointCoord - 1.0;
    float r2 = dot(p, p);
    if (r2 > 1.0) discard;
    float shade = 0.55 + 0.45 * sqrt(1.0 - r2);
    fragColour = vec4(pow(uColour * shade, vec3(1.0 / 2.2)), 1.0);
}
)";

const char* const kOverlayVertex = R"(#version 330 core
layout(location = 0) in vec2 aPixel; // from the top-left corner
layout(location = 1) in vec4 aColour;
uniform vec2 uViewport;
out vec4 vColour;

void main() {
    vColour = aColour;
    vec2 ndc = vec2(2.0 * aPixel.x / uViewport.x - 1.0, 1.0 - 2.0 * aPixel.y / uViewport.y);
    gl_Position = vec4(ndc, 0.0, 1.0);
}
)";

const char* const kOverlayFragment = R"(#version 330 core
in vec4 vColour;
out vec4 fragColour;

void main() { fragColour = vColour; }
)";

} // namespace rubble::viewer::shaders
