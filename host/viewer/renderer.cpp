// host/viewer/renderer.cpp: OpenGL 3.3 core drawing of a DrawList.
#include "host/viewer/renderer.h"

#include <cmath>
#include <cstddef>
#include <vector>

#include <epoxy/gl.h>
#include <glm/gtc/type_ptr.hpp>

#include "host/viewer/gl_program.h"
#include "host/viewer/shaders.h"
#include "host/viewer/shape_mesh.h"
#include "host/viewer/text_overlay.h"

namespace rubble::viewer {
namespace {

constexpr float kTextMargin = 6.0f; // px at scale 1
constexpr glm::vec4 kTextColour{0.92f, 0.94f, 0.96f, 1.0f};
constexpr glm::vec4 kMessageColour{1.0f, 0.55f, 0.35f, 1.0f};
constexpr glm::vec4 kBackdropColour{0.0f, 0.0f, 0.0f, 0.55f};

// One shape's triangles and the instance buffer of the bodies that use it.
struct ShapeBuffers {
    GLuint vao = 0, vertices = 0, indices = 0, instances = 0;
    GLsizei indexCount = 0;
};

// A vertex array with one growing stream buffer behind it.
struct StreamBuffer {
    GLuint vao = 0, buffer = 0;
};

void float4Attribute(GLuint index, GLsizei stride, std::size_t offset, GLuint divisor) {
    glEnableVertexAttribArray(index);
    glVertexAttribPointer(index, 4, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offset));
    glVertexAttribDivisor(index, divisor);
}

// Replaces a buffer's contents; orphaning the old storage keeps the driver from waiting.
void upload(GLuint buffer, const void* data, std::size_t bytes) {
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(bytes), data, GL_STREAM_DRAW);
}

// Two unit axes spanning a plane with the given normal: x and z for an upward normal.
void planeAxes(glm::vec3 n, glm::vec3& u, glm::vec3& v) {
    const glm::vec3 helper = std::abs(n.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 0, 1);
    v = glm::normalize(glm::cross(helper, n));
    u = glm::cross(n, v);
}

} // namespace

glm::vec3 lightDirection() {
    return glm::normalize(glm::vec3(0.45f, 0.85f, 0.30f));
}

struct Renderer::Impl {
    GlProgram body, ground, lines, points, overlay;
    std::vector<ShapeBuffers> shapes;
    GLuint groundVao = 0, groundBuffer = 0;
    StreamBuffer lineStream, pointStream, overlayStream;
    std::vector<OverlayVertex> overlayScratch;
    Palette palette;
    float textScale = 1.0f;

    ~Impl() {
        for (ShapeBuffers& s : shapes) {
            glDeleteVertexArrays(1, &s.vao);
            const GLuint buffers[] = {s.vertices, s.indices, s.instances};
            glDeleteBuffers(3, buffers);
        }
        glDeleteVertexArrays(1, &groundVao);
        glDeleteBuffers(1, &groundBuffer);
        for (StreamBuffer* s : {&lineStream, &pointStream, &overlayStream}) {
            glDeleteVertexArrays(1, &s->vao);
            glDeleteBuffers(1, &s->buffer);
        }
    }

    void createShape(const ShapeGeometry& shape) {
        const RenderMesh mesh = buildRenderMesh(shape);
        ShapeBuffers s;
        s.indexCount = GLsizei(mesh.indices.size());
        glGenVertexArrays(1, &s.vao);
        glGenBuffers(1, &s.vertices);
        glGenBuffers(1, &s.indices);
        glGenBuffers(1, &s.instances);
        glBindVertexArray(s.vao);
        glBindBuffer(GL_ARRAY_BUFFER, s.vertices);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.vertices.size() * sizeof(MeshVertex)),
                     mesh.vertices.data(), GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                              reinterpret_cast<const void*>(offsetof(MeshVertex, position)));
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                              reinterpret_cast<const void*>(offsetof(MeshVertex, normal)));
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, s.indices);
        glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                     GLsizeiptr(mesh.indices.size() * sizeof(std::uint32_t)), mesh.indices.data(),
                     GL_STATIC_DRAW);
        glBindBuffer(GL_ARRAY_BUFFER, s.instances);
        float4Attribute(2, sizeof(BodyInstance), offsetof(BodyInstance, position), 1);
        float4Attribute(3, sizeof(BodyInstance), offsetof(BodyInstance, orientation), 1);
        float4Attribute(4, sizeof(BodyInstance), offsetof(BodyInstance, colour), 1);
        glBindVertexArray(0);
        shapes.push_back(s);
    }

    void createStreams() {
        const float corners[] = {-1, -1, 1, -1, -1, 1, 1, 1};
        glGenVertexArrays(1, &groundVao);
        glGenBuffers(1, &groundBuffer);
        glBindVertexArray(groundVao);
        glBindBuffer(GL_ARRAY_BUFFER, groundBuffer);
        glBufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 2 * sizeof(float), nullptr);

        for (StreamBuffer* s : {&lineStream, &pointStream, &overlayStream}) {
            glGenVertexArrays(1, &s->vao);
            glGenBuffers(1, &s->buffer);
        }
        glBindVertexArray(lineStream.vao);
        glBindBuffer(GL_ARRAY_BUFFER, lineStream.buffer);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                              reinterpret_cast<const void*>(offsetof(LineVertex, position)));
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(LineVertex),
                              reinterpret_cast<const void*>(offsetof(LineVertex, colour)));

        glBindVertexArray(pointStream.vao);
        glBindBuffer(GL_ARRAY_BUFFER, pointStream.buffer);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(glm::vec4), nullptr);

        glBindVertexArray(overlayStream.vao);
        glBindBuffer(GL_ARRAY_BUFFER, overlayStream.buffer);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                              reinterpret_cast<const void*>(offsetof(OverlayVertex, pixel)));
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(OverlayVertex),
                              reinterpret_cast<const void*>(offsetof(OverlayVertex, colour)));
        glBindVertexArray(0);
    }

    void drawBodies(const DrawList& frame, const glm::mat4& viewProjection, glm::vec3 eye) {
        glUseProgram(body.id());
        glUniformMatrix4fv(body.uniform("uViewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        glUniform3fv(body.uniform("uEye"), 1, glm::value_ptr(eye));
        const glm::vec3 light = lightDirection();
        glUniform3fv(body.uniform("uLightDirection"), 1, glm::value_ptr(light));
        for (std::size_t k = 0; k < shapes.size() && k < frame.instances.size(); ++k) {
            const std::vector<BodyInstance>& list = frame.instances[k];
            if (list.empty() || shapes[k].indexCount == 0) continue;
            upload(shapes[k].instances, list.data(), list.size() * sizeof(BodyInstance));
            glBindVertexArray(shapes[k].vao);
            glDrawElementsInstanced(GL_TRIANGLES, shapes[k].indexCount, GL_UNSIGNED_INT, nullptr,
                                    GLsizei(list.size()));
        }
    }

    void drawGrounds(const DrawList& frame, const glm::mat4& viewProjection) {
        if (frame.grounds.empty()) return;
        glUseProgram(ground.id());
        glUniformMatrix4fv(ground.uniform("uViewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        const glm::vec3 light = lightDirection();
        glUniform3fv(ground.uniform("uLightDirection"), 1, glm::value_ptr(light));
        glUniform3fv(ground.uniform("uBase"), 1, glm::value_ptr(palette.ground));
        glUniform3fv(ground.uniform("uBackground"), 1, glm::value_ptr(palette.background));
        glBindVertexArray(groundVao);
        // The ground sits a hair behind coplanar faces resting on it.
        glEnable(GL_POLYGON_OFFSET_FILL);
        glPolygonOffset(1.0f, 1.0f);
        for (const GroundPlane& g : frame.grounds) {
            glm::vec3 u, v;
            planeAxes(g.normal, u, v);
            const glm::vec3 origin = g.normal * glm::dot(g.normal, g.centre);
            const glm::vec2 offset(glm::dot(g.centre - origin, u), glm::dot(g.centre - origin, v));
            glUniform3fv(ground.uniform("uCentre"), 1, glm::value_ptr(g.centre));
            glUniform3fv(ground.uniform("uAxisU"), 1, glm::value_ptr(u));
            glUniform3fv(ground.uniform("uAxisV"), 1, glm::value_ptr(v));
            glUniform3fv(ground.uniform("uNormal"), 1, glm::value_ptr(g.normal));
            glUniform2fv(ground.uniform("uGridOffset"), 1, glm::value_ptr(offset));
            glUniform1f(ground.uniform("uHalfSize"), g.halfSize);
            glUniform1f(ground.uniform("uFadeStart"), 0.55f * g.halfSize);
            glUniform1f(ground.uniform("uFadeEnd"), 0.98f * g.halfSize);
            glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        }
        glDisable(GL_POLYGON_OFFSET_FILL);
    }

    void drawLines(const DrawList& frame, const glm::mat4& viewProjection) {
        if (frame.lines.empty()) return;
        glUseProgram(lines.id());
        glUniformMatrix4fv(lines.uniform("uViewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        upload(lineStream.buffer, frame.lines.data(), frame.lines.size() * sizeof(LineVertex));
        glBindVertexArray(lineStream.vao);
        // Debug lines show through bodies: contacts and joints are inside them.
        glDisable(GL_DEPTH_TEST);
        glDrawArrays(GL_LINES, 0, GLsizei(frame.lines.size()));
        glEnable(GL_DEPTH_TEST);
    }

    void drawParticles(const DrawList& frame, const glm::mat4& viewProjection, const Camera& camera,
                       int height) {
        if (frame.particles.empty()) return;
        glUseProgram(points.id());
        glUniformMatrix4fv(points.uniform("uViewProjection"), 1, GL_FALSE,
                           glm::value_ptr(viewProjection));
        const float pixelsPerUnit = float(height) / (2.0f * std::tan(0.5f * camera.fovY));
        glUniform1f(points.uniform("uPixelsPerUnitAtOne"), pixelsPerUnit);
        glUniform3fv(points.uniform("uColour"), 1, glm::value_ptr(palette.particles));
        upload(pointStream.buffer, frame.particles.data(),
               frame.particles.size() * sizeof(glm::vec4));
        glBindVertexArray(pointStream.vao);
        glEnable(GL_PROGRAM_POINT_SIZE);
        glDrawArrays(GL_POINTS, 0, GLsizei(frame.particles.size()));
        glDisable(GL_PROGRAM_POINT_SIZE);
    }

    void drawOverlay(const DrawList& frame, int width, int height) {
        if (frame.text.empty() && frame.message.empty()) return;
        std::vector<OverlayVertex>& v = overlayScratch;
        v.clear();
        const float margin = kTextMargin * textScale;
        float widest = 0.0f, y = margin;
        std::vector<std::pair<float, std::size_t>> rows; // top of each line, index in text
        for (std::size_t i = 0; i < frame.text.size(); ++i) {
            const glm::vec2 size = textSize(frame.text[i], textScale);
            widest = std::max(widest, size.x);
            rows.emplace_back(y, i);
            y += size.y;
        }
        float messageTop = y;
        if (!frame.message.empty()) {
            widest = std::max(widest, textSize(frame.message, textScale).x);
            y += textSize(frame.message, textScale).y;
        }
        appendRect(v, glm::vec2(0.0f), glm::vec2(widest + 2.0f * margin, y + 0.5f * margin),
                   kBackdropColour);
        for (const auto& [top, i] : rows)
            appendText(v, glm::vec2(margin, top + 0.25f * margin), frame.text[i], kTextColour,
                       textScale);
        if (!frame.message.empty())
            appendText(v, glm::vec2(margin, messageTop + 0.25f * margin), frame.message,
                       kMessageColour, textScale);

        glUseProgram(overlay.id());
        glUniform2f(overlay.uniform("uViewport"), float(width), float(height));
        upload(overlayStream.buffer, v.data(), v.size() * sizeof(OverlayVertex));
        glBindVertexArray(overlayStream.vao);
        glDisable(GL_DEPTH_TEST);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(v.size()));
        glEnable(GL_DEPTH_TEST);
    }
};

Result<Renderer> Renderer::create(std::span<const ShapeGeometry> shapes) {
    auto impl = std::make_unique<Impl>();
    Result<GlProgram> body =
        GlProgram::create("body", shaders::kBodyVertex, shaders::kBodyFragment);
    if (!body) return body.error();
    Result<GlProgram> ground =
        GlProgram::create("ground", shaders::kGroundVertex, shaders::kGroundFragment);
    if (!ground) return ground.error();
    Result<GlProgram> lines =
        GlProgram::create("line", shaders::kLineVertex, shaders::kLineFragment);
    if (!lines) return lines.error();
    Result<GlProgram> points =
        GlProgram::create("point", shaders::kPointVertex, shaders::kPointFragment);
    if (!points) return points.error();
    Result<GlProgram> overlay =
        GlProgram::create("overlay", shaders::kOverlayVertex, shaders::kOverlayFragment);
    if (!overlay) return overlay.error();
    impl->body = std::move(*body);
    impl->ground = std::move(*ground);
    impl->lines = std::move(*lines);
    impl->points = std::move(*points);
    impl->overlay = std::move(*overlay);
    impl->createStreams();
    for (const ShapeGeometry& s : shapes) impl->createShape(s);
    RUBBLE_TRY(checkGl("creating the renderer's buffers"));
    return Renderer(std::move(impl));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
Renderer::~Renderer() = default;

Palette& Renderer::palette() {
    return impl_->palette;
}
void Renderer::setTextScale(float scale) {
    impl_->textScale = scale;
}

void Renderer::draw(const DrawList& frame, const Camera& camera, int width, int height) {
    Impl& r = *impl_;
    glViewport(0, 0, width, height);
    const glm::vec3 bg = glm::pow(r.palette.background, glm::vec3(1.0f / 2.2f));
    glClearColor(bg.r, bg.g, bg.b, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDisable(GL_CULL_FACE);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);

    const glm::mat4 viewProjection =
        camera.projection(float(width) / float(height)) * camera.view();
    r.drawGrounds(frame, viewProjection);
    r.drawBodies(frame, viewProjection, camera.eye());
    r.drawParticles(frame, viewProjection, camera, height);
    r.drawLines(frame, viewProjection);
    r.drawOverlay(frame, width, height);
    glBindVertexArray(0);
    glUseProgram(0);
}

} // namespace rubble::viewer
