// host/gpu/lcp_convergence.cpp: the device solvers one sweep at a time on a frozen contact set.
#include "host/gpu/lcp_convergence.h"

#include "host/gpu/lcp_jacobi.h"
#include "host/gpu/pipeline.h"
#include "host/world/world_state.h"

namespace rubble::gpu {

Result<Iterates> lcpJacobiIteratesOnDevice(const Context& c, const DenseLcp& p, int iterations,
                                           float relaxation) {
    DenseLcp start = p;
    std::fill(start.lambda.begin(), start.lambda.end(), 0.0f);
    LcpBuffers lcp;
    RUBBLE_TRY(uploadLcp(c, start, lcp));
    Iterates out;
    std::vector<float> lambda;
    for (int k = 0; k < iterations; ++k) {
        RUBBLE_TRY(iterateLcpJacobi(c, lcp, 1, relaxation, lcp.status));
        RUBBLE_TRY(downloadLcpLambda(c, lcp, lambda));
        out.push_back(lambda);
    }
    return out;
}

Result<Iterates> jacobiIteratesOnDevice(std::shared_ptr<Context> c, const WorldState& s,
                                        const FrozenProblem& p, int iterations,
                                        float relaxation) {
    Result<PipelineHandle> made = Pipeline::create(std::move(c), s);
    RUBBLE_TRY(made);
    Pipeline& pipeline = **made;
    const FrozenContacts& set = p.set;
    RUBBLE_TRY(pipeline.uploadContacts(set.contacts));
    RUBBLE_TRY(pipeline.buildJacobiRows(set.params, false));
    Iterates out;
    std::vector<shared::ContactRow> rows(set.contacts.size());
    for (int k = 0; k < iterations; ++k) {
        // The start velocities again; the rows keep the impulses of the last sweep, which the
        // first gather applies.
        RUBBLE_TRY(pipeline.uploadBodies(s));
        RUBBLE_TRY(pipeline.solveJacobi(1, relaxation, false));
        RUBBLE_TRY(download(pipeline.context(), pipeline.contacts().rows, std::span(rows)));
        out.push_back(denseLambda(rows, p.dense.stride));
    }
    return out;
}

} // namespace rubble::gpu
