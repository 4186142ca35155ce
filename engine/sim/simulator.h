#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sim/controls.h"
#include "sim/sim_model.h"

namespace facesr {

// Quasistatic solve per frame: Newton on the total energy, a block-Jacobi
// preconditioned CG for each Newton step, backtracking (Armijo) line search,
// warm start from the previous frame.
struct SolverOptions {
  double newton_tol = 1e-3;  // stop when |∇E_free| ≤ tol · reference residual (see StepStats)
  int newton_max = 20;
  double cg_tol = 1e-2;      // relative residual of each linear solve
  int cg_max = 400;
  int line_search_max = 16;  // halvings
  // Below this relative residual Newton uses the exact (unfixed) Hessian,
  // falling back to the definiteness-fixed one on negative curvature.
  double exact_hessian_below = 1e-2;
  // Start each frame from the linear extrapolation of the last two solved
  // frames rather than the last one (smooth performances need fewer Newton steps).
  bool extrapolate = true;
  // With a contact source (HR collisions): detect contacts at the first
  // `contact_refresh_iters` Newton iterations, then hold the planes fixed; on
  // convergence re-detect, and go on while the deepest penetration exceeds
  // penetration_tol_cm, up to contact_detections_max detections per frame.
  int contact_refresh_iters = 3;
  int contact_detections_max = 6;
  double penetration_tol_cm = 0.03;
  // Divergence detection and recovery (sim/recovering_simulator.h): a frame
  // counts as diverged when its forces or positions are not finite, its
  // relative residual ends above diverged_residual (no closer to equilibrium
  // than the rest pose with this frame's bones), or more tets are inverted
  // than at rest plus max(32, diverged_inverted_fraction · tets). Such a
  // frame is solved again from the last good state, then in control
  // sub-steps, then in sub-steps with the accurate preset; if all fail the
  // simulator goes back to the last good state and says so (StepStatus::Diverged).
  bool recover = true;
  double diverged_residual = 1.0;
  double diverged_inverted_fraction = 0.02;
  int recovery_substeps = 4;
};

// The game preset: at most 3 Newton steps of at most 60 CG iterations per
// frame, looser tolerances (`--solver realtime`, the runtime's default).
inline SolverOptions realtime_solver() {
  SolverOptions o;
  o.newton_tol = 1e-2;
  o.newton_max = 3;
  o.cg_tol = 0.05;
  o.cg_max = 60;
  return o;
}

// What became of a frame. Unconverged: stopped at an iteration cap above
// tolerance but sane. Recovered: diverged at first, then solved by the
// recovery ladder (see SolverOptions::recover). Diverged: every recovery
// failed; the state is the last good frame's.
enum class StepStatus : int32_t { Converged = 0, Unconverged = 1, Recovered = 2, Diverged = 3 };

struct StepStats {
  int newton_iters = 0;
  int cg_iters = 0;           // summed over Newton iterations
  int line_search_halvings = 0;
  // |∇E over free nodes| / reference, the reference being the same norm at
  // the undeformed mesh with this frame's bone motion and controls (floored at
  // 1e-3 · μ · h² so that a control-free frame is judged in absolute terms).
  double rel_residual = 0;
  double energy = 0;          // kPa·cm³ (mJ)
  bool converged = false;
  int inverted_tets = 0;      // tets with det F ≤ 0 after the step
  double ms = 0;              // wall time of the step
  // With a contact source: penetrating nodes and the deepest penetration (cm)
  // at the final positions (measured even when contacts are not resolved).
  int contacts = 0;
  double max_penetration_cm = 0;
  std::vector<double> residuals;  // rel_residual before each Newton iteration and at the end
  bool finite = true;             // forces stayed finite throughout the solve
  StepStatus status = StepStatus::Unconverged;  // set by the recovering wrapper (converged/unconverged without it)
  int recoveries = 0;             // extra solves the recovery ladder ran on this frame
};

class Simulator {
 public:
  virtual ~Simulator() = default;
  // Solves one frame; throws Error on invalid controls (state unchanged).
  virtual StepStats step(const Controls& c) = 0;
  virtual void reset() = 0;  // back to the rest pose (no warm start)
  // Current node positions (node × 3) and embedded face surface (vertex × 3), cm.
  virtual void nodes(std::vector<double>& x) const = 0;
  virtual void surface(std::vector<double>& s) const = 0;
  virtual void set_nodes(const std::vector<double>& x) = 0;  // warm start from given positions
  // Net force −∇E on each node at the current positions under these controls
  // (node × 3; bone nodes 0), without solving. For parity tests and tools.
  virtual void forces(const Controls& c, std::vector<double>& f) = 0;
  virtual std::string device() const = 0;
  // Mean wall time (ms) of one matrix-free stiffness product K·p at the
  // current state, over `repetitions` products (for benchmarks).
  virtual double time_stiffness_product(int repetitions) = 0;
  virtual const SimModel& model() const = 0;
  virtual const SolverOptions& options() const = 0;
  virtual void set_options(const SolverOptions& opt) = 0;
};

// True when a step's result is broken (see SolverOptions::recover); the
// node positions' finiteness is checked by the caller that has them.
bool step_diverged(const StepStats& st, const SimModel& m, const SolverOptions& opt, int rest_inverted);

class ContactSource;
// With `contacts`, every Newton iteration detects contacts and resolves them
// with penalty planes (sim/contact.h); with resolve_contacts = false they are
// only measured after each step (for comparisons without collision handling).
std::unique_ptr<Simulator> make_cpu_simulator(const SimModel& model, const SolverOptions& opt = {},
                                              std::shared_ptr<ContactSource> contacts = nullptr,
                                              bool resolve_contacts = true);

// Face surface from node positions via the embedding.
void embed_surface(const SimModel& m, const std::vector<double>& x, std::vector<double>& s);

}  // namespace facesr
