#include "solver/step_stats.hpp"

#include "common/named_enum.hpp"

namespace nmdp {

namespace {
constexpr EnumName<StepStatus> kStepStatuses[] = {
    {StepStatus::Converged, "converged"},
    {StepStatus::ProjectionFailed, "manifold projection diverged"},
    {StepStatus::TrustRegionFailed, "trust-region penalty exceeded beta_max"},
    {StepStatus::MaxIterations, "outer-iteration limit reached"},
    {StepStatus::QpFailed, "contact QP failed"},
    {StepStatus::NonFinite, "non-finite state"},
    {StepStatus::Diverged, "diverged (the energy rose beyond what the controller can supply)"},
    {StepStatus::Cancelled, "interrupted"},
};
}  // namespace

const char* toString(StepStatus status) { return nameOf(kStepStatuses, status); }

void addIterationCounts(StepStats& total, const StepStats& attempt) {
  total.outer_iterations += attempt.outer_iterations;
  total.g_evaluations += attempt.g_evaluations;
  total.projections += attempt.projections;
  total.newton_iterations += attempt.newton_iterations;
  total.rejected += attempt.rejected;
}

}  // namespace nmdp
