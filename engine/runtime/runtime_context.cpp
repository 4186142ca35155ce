#include "runtime/runtime_context.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "core/number_text.h"
#include "core/progress.h"
#include "mesh/tri_mesh.h"
#include "runtime/sr_inference.h"
#include "sim/cl_simulator.h"

namespace facesr {

namespace {

using Clock = std::chrono::steady_clock;

// The capture tolerance of sim/controls.h: slight overshoots clamped, the rest refused.
float checked_weight(const std::string& name, float value) {
  require(std::isfinite(value), "weight '" + name + "' is not finite");
  // Compared in float: 1.1f is a little above the double 1.1.
  const float low = float(1 - kWeightTolerance), high = float(kWeightTolerance);
  require(value >= low && value <= high, "weight '" + name + "' is " + number_text(value, 6) + ", outside [" +
                                             number_text(low, 3) + ", " + number_text(high, 3) +
                                             "] (values within it are clamped into [0, 1])");
  return std::clamp(value, 0.0f, 1.0f);
}

void require_finite(const Vec3& v, const std::string& what) {
  require(std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()), what + " is not finite");
}
void require_positive(double v, const std::string& what) {
  require(std::isfinite(v) && v > 0, what + " must be a positive number (got " + std::to_string(v) + ")");
}

// One frame moving through the pipeline.
struct Job {
  int64_t frame = 0;
  Controls controls;
  Clock::time_point submitted;
  std::vector<float> lr_disp;
  FrameResult result;
  std::exception_ptr error;
  bool done = false;
};

}  // namespace

struct RuntimeContext::Impl {
  std::shared_ptr<const RuntimeModel> compiled;
  std::shared_ptr<const Rig> rig;  // compiled's, for brevity
  std::unique_ptr<Simulator> sim;
  std::unique_ptr<SrInference> sr;
  Controls controls;
  std::map<int, PointSpring> springs;
  std::map<int, SphereCollider> spheres;
  int next_id = 1;
  int64_t next_frame = 0;
  FrameResult result;

  // Pipeline: the simulation thread takes jobs from sim_queue and hands them
  // to the inference thread through sr_queue; wait() takes finished jobs from
  // the front of `jobs` (submission order).
  std::mutex mu;
  std::condition_variable cv;
  std::deque<std::shared_ptr<Job>> jobs, sim_queue, sr_queue;
  std::thread sim_thread, sr_thread;
  bool stopping = false;

  Controls frame_controls() const {
    Controls c = controls;
    for (const auto& [id, s] : springs) c.springs.push_back(s);
    for (const auto& [id, s] : spheres) c.spheres.push_back(s);
    return c;
  }

  void simulate(Job& j) {
    const auto t0 = Clock::now();
    const StepStats st = sim->step(j.controls);
    std::vector<double> x, s;
    sim->nodes(x);
    sim->surface(s);
    const std::vector<double>& rest = compiled->lr_model.rest;
    j.lr_disp.resize(x.size());
    for (size_t i = 0; i < x.size(); ++i) j.lr_disp[i] = float(x[i] - rest[i]);
    j.result.embedded.resize(s.size());
    const std::vector<double>& surf_rest = compiled->lr_model.surf_rest;
    for (size_t i = 0; i < s.size(); ++i) j.result.embedded[i] = compiled->hr_rest[i] + float(s[i] - surf_rest[i]);
    for (double v : j.lr_disp) require(std::isfinite(v), "simulation: frame " + std::to_string(j.frame) + " is not finite");
    j.result.frame = j.frame;
    j.result.newton_iterations = st.newton_iters;
    j.result.cg_iterations = st.cg_iters;
    j.result.relative_residual = st.rel_residual;
    j.result.status = st.status;
    j.result.inverted_tets = st.inverted_tets;
    j.result.recoveries = st.recoveries;
    j.result.simulation_ms = 1e3 * seconds_since(t0);
  }

  void super_resolve(Job& j) {
    const auto t0 = Clock::now();
    std::vector<float>& p = j.result.positions;
    p.resize(compiled->hr_rest.size());
    sr->infer(j.lr_disp.data(), p.data());
    for (size_t i = 0; i < p.size(); ++i) p[i] += compiled->hr_rest[i];
    normals(p, j.result.normals);
    j.result.inference_ms = 1e3 * seconds_since(t0);
    j.result.total_ms = 1e3 * seconds_since(j.submitted);
  }

  void normals(const std::vector<float>& p, std::vector<float>& n) const {
    Points V(long(p.size() / 3), 3);
    for (size_t i = 0; i < p.size(); ++i) V.data()[i] = p[i];
    const Points N = vertex_normals(V, rig->surface_tris);
    n.assign(N.data(), N.data() + N.size());
  }

  void rest_result() {
    result = FrameResult{};
    result.positions = compiled->hr_rest;
    result.embedded = compiled->hr_rest;
    normals(compiled->hr_rest, result.normals);
  }

  void worker(bool is_sim) {
    auto& in = is_sim ? sim_queue : sr_queue;
    for (;;) {
      std::shared_ptr<Job> j;
      {
        std::unique_lock<std::mutex> lock(mu);
        cv.wait(lock, [&] { return stopping || !in.empty(); });
        if (stopping && in.empty()) return;
        j = in.front();
        in.pop_front();
      }
      if (!j->error) {
        try {
          is_sim ? simulate(*j) : super_resolve(*j);
        } catch (...) {
          j->error = std::current_exception();
        }
      }
      {
        std::lock_guard<std::mutex> lock(mu);
        if (is_sim)
          sr_queue.push_back(j);
        else
          j->done = true;
      }
      cv.notify_all();
    }
  }

  void start_threads() {
    if (sim_thread.joinable()) return;
    sim_thread = std::thread([this] { worker(true); });
    sr_thread = std::thread([this] { worker(false); });
  }

  void stop_threads() {
    {
      std::lock_guard<std::mutex> lock(mu);
      stopping = true;
    }
    cv.notify_all();
    if (sim_thread.joinable()) sim_thread.join();
    if (sr_thread.joinable()) sr_thread.join();
    stopping = false;
  }

  void drain() {
    std::unique_lock<std::mutex> lock(mu);
    cv.wait(lock, [&] {
      for (const auto& j : jobs)
        if (!j->done) return false;
      return true;
    });
    jobs.clear();
  }
};

RuntimeContext::RuntimeContext(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model,
                               const RuntimeOptions& opt)
    : RuntimeContext(compile_runtime_model(std::move(rig), std::move(model)), opt) {}

RuntimeContext::RuntimeContext(std::shared_ptr<const RuntimeModel> compiled, const RuntimeOptions& opt)
    : impl_(std::make_unique<Impl>()) {
  require(compiled != nullptr, "runtime: no compiled runtime model");
  Impl& m = *impl_;
  m.compiled = std::move(compiled);
  m.rig = m.compiled->rig;
  ClSimulatorOptions cl;
  cl.device = opt.device;
  cl.single_precision = opt.lr_single_precision;
  const bool split = opt.split_device && !opt.cpu_inference;
  if (split) cl.device.parts = 2, cl.device.part = 0;
  m.sim = make_cl_simulator(m.compiled->lr_model, opt.solver, cl);
  if (opt.cpu_inference) {
    m.sr = make_cpu_inference(m.compiled->model, m.compiled->plan);
  } else {
    ClInferenceOptions io;
    io.device = opt.device;
    if (split) io.device.parts = 2, io.device.part = 1;
    m.sr = make_cl_inference(m.compiled->model, io, m.compiled->plan);
  }
  m.controls.weights.assign(size_t(m.rig->num_blendshapes()), 0.0f);
  m.rest_result();
}

RuntimeContext::~RuntimeContext() {
  impl_->drain();
  impl_->stop_threads();
}

const Rig& RuntimeContext::rig() const { return *impl_->rig; }
const std::shared_ptr<const RuntimeModel>& RuntimeContext::compiled() const { return impl_->compiled; }
int RuntimeContext::num_weights() const { return impl_->rig->num_blendshapes(); }
int RuntimeContext::num_vertices() const { return impl_->rig->num_surface_vertices(); }
std::string RuntimeContext::device() const { return impl_->sim->device() + " + " + impl_->sr->device(); }

void RuntimeContext::set_weight(int index, float value) {
  require(index >= 0 && index < num_weights(), "weight index " + std::to_string(index) + " is out of range [0, " +
                                                   std::to_string(num_weights()) + ")");
  const std::string& name = impl_->rig->blendshape_names[size_t(index)];
  impl_->controls.weights[size_t(index)] = checked_weight(name, value);
}

void RuntimeContext::set_weight(const std::string& name, float value) {
  const auto& names = impl_->rig->blendshape_names;
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return set_weight(int(i), value);
  throw Error("no blendshape named '" + name + "' in rig '" + impl_->rig->name + "'");
}

void RuntimeContext::set_weights(const std::vector<float>& w) {
  require(int(w.size()) == num_weights(),
          "set_weights: " + std::to_string(w.size()) + " weights given, the rig has " + std::to_string(num_weights()));
  const auto& names = impl_->rig->blendshape_names;
  std::vector<float> clamped(w.size());
  for (size_t i = 0; i < w.size(); ++i) clamped[i] = checked_weight(names[i], w[i]);
  impl_->controls.weights = std::move(clamped);
}

void RuntimeContext::set_jaw(const Mat3& R, const Vec3& t) {
  require(R.allFinite(), "jaw rotation is not finite");
  require_finite(t, "jaw translation");
  require((R * R.transpose() - Mat3::Identity()).norm() < 1e-3 && R.determinant() > 0,
          "jaw rotation is not a rotation matrix (R Rᵀ must be I and det R = 1)");
  impl_->controls.jaw_override = true;
  impl_->controls.jaw_R = R;
  impl_->controls.jaw_t = t;
}

void RuntimeContext::clear_jaw() { impl_->controls.jaw_override = false; }

int RuntimeContext::add_spring(int vertex, const Vec3& target, double stiffness) {
  require(vertex >= 0 && vertex < num_vertices(), "spring vertex " + std::to_string(vertex) +
                                                       " is out of range [0, " + std::to_string(num_vertices()) + ")");
  require_finite(target, "spring target");
  require_positive(stiffness, "spring stiffness");
  PointSpring s;
  s.vertex = vertex;
  s.target = target;
  s.stiffness = stiffness;
  impl_->springs[impl_->next_id] = s;
  return impl_->next_id++;
}

void RuntimeContext::move_spring(int id, const Vec3& target) {
  auto it = impl_->springs.find(id);
  require(it != impl_->springs.end(), "no spring with id " + std::to_string(id));
  require_finite(target, "spring target");
  it->second.target = target;
}

void RuntimeContext::remove_spring(int id) {
  require(impl_->springs.erase(id) == 1, "no spring with id " + std::to_string(id));
}

int RuntimeContext::add_sphere(const Vec3& centre, double radius, double stiffness) {
  require_finite(centre, "sphere centre");
  require_positive(radius, "sphere radius");
  require_positive(stiffness, "sphere stiffness");
  SphereCollider s;
  s.centre = centre;
  s.radius = radius;
  s.stiffness = stiffness;
  impl_->spheres[impl_->next_id] = s;
  return impl_->next_id++;
}

void RuntimeContext::move_sphere(int id, const Vec3& centre) {
  auto it = impl_->spheres.find(id);
  require(it != impl_->spheres.end(), "no sphere with id " + std::to_string(id));
  require_finite(centre, "sphere centre");
  it->second.centre = centre;
}

void RuntimeContext::remove_sphere(int id) {
  require(impl_->spheres.erase(id) == 1, "no sphere with id " + std::to_string(id));
}

void RuntimeContext::reset() {
  Impl& m = *impl_;
  m.drain();
  m.sim->reset();
  m.controls = Controls{};
  m.controls.weights.assign(size_t(num_weights()), 0.0f);
  m.springs.clear();
  m.spheres.clear();
  m.next_frame = 0;
  m.rest_result();
}

int RuntimeContext::pending() const {
  std::lock_guard<std::mutex> lock(impl_->mu);
  return int(impl_->jobs.size());
}

void RuntimeContext::step() {
  Impl& m = *impl_;
  require(pending() == 0, "step: " + std::to_string(pending()) +
                              " asynchronous frames are pending; wait for them first");
  Job j;
  j.frame = m.next_frame;
  j.controls = m.frame_controls();
  j.submitted = Clock::now();
  m.simulate(j);
  m.super_resolve(j);
  ++m.next_frame;
  m.result = std::move(j.result);
}

void RuntimeContext::step_async() {
  Impl& m = *impl_;
  auto j = std::make_shared<Job>();
  j->controls = m.frame_controls();
  validate_controls(m.compiled->lr_model, j->controls);  // bad controls fail here, not at wait()
  {
    std::lock_guard<std::mutex> lock(m.mu);
    require(m.jobs.size() < 2, "step_async: 2 frames are already pending; call wait first");
    j->frame = m.next_frame++;
    j->submitted = Clock::now();
    m.jobs.push_back(j);
    m.sim_queue.push_back(j);
  }
  m.start_threads();
  m.cv.notify_all();
}

int64_t RuntimeContext::wait() {
  Impl& m = *impl_;
  std::shared_ptr<Job> j;
  {
    std::unique_lock<std::mutex> lock(m.mu);
    require(!m.jobs.empty(), "wait: no frame is pending (call step_async first)");
    j = m.jobs.front();
    m.cv.wait(lock, [&] { return j->done; });
    m.jobs.pop_front();
  }
  if (j->error) std::rethrow_exception(j->error);
  m.result = std::move(j->result);
  return m.result.frame;
}

const FrameResult& RuntimeContext::result() const { return impl_->result; }

}  // namespace facesr
