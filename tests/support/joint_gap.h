// tests/support/joint_gap.h: how far a set of joints is from holding, measured from the scene's
// joint descriptions alone (not from the solver's Joint records or its error report): each
// anchor and hinge axis taken into its two bodies' frames at reference poses, then compared at
// other poses.
#pragma once

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "rubble/scene.h"
#include "rubble/shared/body.h"

namespace rubble::test {

/// The largest anchor separation (m) and hinge axis misalignment (rad) over the joints.
struct JointGap {
    double linear = 0.0;
    double angular = 0.0;
};

class JointGapProbe {
  public:
    /// Each joint's anchor and axis (world, as the scene gives them) in its bodies' frames at
    /// `poses`, the poses at which the joints hold.
    JointGapProbe(std::span<const JointDesc> joints, std::span<const shared::BodyPose> poses)
        : joints_(joints.begin(), joints.end()) {
        for (const JointDesc& j : joints_) {
            const Frame a = frame(poses[j.a]), b = frame(poses[j.b]);
            const glm::dvec3 anchor(j.anchor), axis = glm::normalize(glm::dvec3(j.axis));
            local_.push_back({glm::inverse(a.q) * (anchor - a.x),
                              glm::inverse(b.q) * (anchor - b.x), glm::inverse(a.q) * axis,
                              glm::inverse(b.q) * axis});
        }
    }

    /// The joints' worst separation and misalignment at `poses`.
    JointGap at(std::span<const shared::BodyPose> poses) const {
        JointGap gap;
        for (std::size_t k = 0; k < joints_.size(); ++k) {
            const Frame a = frame(poses[joints_[k].a]), b = frame(poses[joints_[k].b]);
            const Local& l = local_[k];
            gap.linear = std::max(gap.linear,
                                  glm::length((a.x + a.q * l.anchorA) - (b.x + b.q * l.anchorB)));
            if (joints_[k].type != JointType::Hinge) continue;
            const glm::dvec3 u = a.q * l.axisA, v = b.q * l.axisB;
            gap.angular =
                std::max(gap.angular, std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)));
        }
        return gap;
    }

  private:
    struct Frame {
        glm::dvec3 x;
        glm::dquat q;
    };
    struct Local {
        glm::dvec3 anchorA, anchorB, axisA, axisB;
    };
    static Frame frame(const shared::BodyPose& p) {
        // Poses store x, y, z, w; glm's quaternion constructor takes w first.
        return {glm::dvec3(p.position.x, p.position.y, p.position.z),
                glm::normalize(glm::dquat(p.orientation.w, p.orientation.x, p.orientation.y,
                                          p.orientation.z))};
    }
    std::vector<JointDesc> joints_;
    std::vector<Local> local_;
};

} // namespace rubble::test
