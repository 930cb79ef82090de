// The render thread: plan a step under the lock, render it outside, publish.
#include "render_session.h"

#include <algorithm>
#include <cstdio>

#include "io/atomic_file.h"
#include "io/camera_setup.h"
#include "io/image_output.h"
#include "io/scene_error.h"
#include "progressive.h"
#include "wavefront/engines.h"

namespace pt::live {

using Clock = std::chrono::steady_clock;

namespace {

/// Whether a frame costs the same under `a` and `b`: all but the sample target and the preview divisor agree.
bool same_cost(ViewSettings a, ViewSettings b) {
  a.samples = b.samples = 0;
  a.preview = b.preview = 0;
  return a == b;
}

}  // namespace

/// The view being rendered: its accumulated samples and what they cost.
struct RenderSession::Progress {
  uint64_t version = 0;  ///< 0: nothing rendered yet
  int divisor = 1;       ///< resolution divisor (above 1: a preview while the camera moves)
  Accumulation acc;
  std::shared_ptr<const Film> film;  ///< of the last step (shared with its frame)
  uint32_t done = 0;
  bool complete = false;
  uint64_t rays = 0;
  double render_seconds = 0;
  double estimated_relative_rmse = -1;  ///< of the accumulated image; < 0: none (under 4 samples)
  Clock::time_point started;            ///< when the view changed to this version
};

/// What the thread does next.
struct RenderSession::Step {
  enum class Kind : uint8_t { kRestart, kContinue, kWriteJob } kind = Kind::kRestart;
  View view;
  int divisor = 1;
  uint32_t samples = 1;
  Clock::time_point changed_at;
};

RenderSession::RenderSession(const Scene& scene, const SceneBvh4& bvh, SessionConfig config)
    : scene_(scene), bvh_(bvh), config_(std::move(config)) {
  view_.camera = config_.camera;
  view_.settings = config_.settings;
  view_.version = 1;
  view_.settings_version = 1;
  changed_at_ = Clock::now();
  moving_until_ = changed_at_;
  thread_ = std::thread([this] { run(); });
}

RenderSession::~RenderSession() { stop(); }

void RenderSession::stop() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
    cancel_.store(true);
  }
  work_cv_.notify_all();
  frame_cv_.notify_all();
  if (config_.frames_changed) config_.frames_changed();
  if (thread_.joinable()) thread_.join();
}

RenderSession::View RenderSession::view() const {
  std::lock_guard lock(mutex_);
  return view_;
}

uint64_t RenderSession::changed() {
  const Clock::time_point now = Clock::now();
  ++view_.version;
  changed_at_ = now;
  if (!running_may_finish_ && !cancel_.load()) {
    cancelled_at_ = now;
    chunks_after_cancel_.store(0);
    cancel_.store(true);
  }
  if (job_.state == JobState::kRendering) {
    job_.state = JobState::kCancelled;
    job_.message = "the view changed";
  }
  work_cv_.notify_all();
  return view_.version;
}

uint64_t RenderSession::navigate(const NavInput& in) {
  std::lock_guard lock(mutex_);
  const ViewSettings& s = view_.settings;
  ViewCamera& c = view_.camera;
  moving_until_ = in.moving ? Clock::now() + config_.still_after : Clock::now();
  switch (in.kind) {
    case NavInput::Kind::kOrbit: c = orbit(c, in.dx, in.dy, s.width, s.height); break;
    case NavInput::Kind::kPan:
      c = pan(c, in.dx, in.dy, resolve_camera(c, s.width, s.height).tan_half_vfov, s.height, config_.limits);
      break;
    case NavInput::Kind::kZoom: c = zoom(c, in.dx, config_.limits); break;
    case NavInput::Kind::kReset: c = config_.camera; break;
    case NavInput::Kind::kStill: work_cv_.notify_all(); return view_.version;
  }
  return changed();
}

uint64_t RenderSession::set_camera(const ViewCamera& camera) {
  std::lock_guard lock(mutex_);
  view_.camera = camera;
  moving_until_ = Clock::now();
  return changed();
}

uint64_t RenderSession::set_settings(const ViewSettings& settings) {
  std::lock_guard lock(mutex_);
  if (settings == view_.settings) return view_.version;
  view_.settings = settings;
  ++view_.settings_version;
  return changed();
}

std::shared_ptr<const Frame> RenderSession::frame_after(uint64_t after, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(mutex_);
  const uint64_t failures = failures_;
  // A failure of the current view ends the wait too when it came before the request: no frame follows
  // until the next change.
  auto ready = [&] {
    return stop_ || failures_ != failures || error_version_ == view_.version || (latest_ && latest_->info.id != after);
  };
  frame_cv_.wait_for(lock, timeout, ready);
  return latest_ && latest_->info.id != after ? latest_ : nullptr;
}

std::string RenderSession::start_job(const std::filesystem::path& png, bool replace) {
  std::lock_guard lock(mutex_);
  if (job_.state == JobState::kRendering) return "a render is already running (" + job_.path.string() + ")";
  if (error_version_ == view_.version)
    return "the render of this view failed (" + render_error_ + "); change the view to render again";
  job_ = RenderJob{JobState::kRendering, png, replace, view_.version, 0.0, {}};
  work_cv_.notify_all();
  return {};
}

bool RenderSession::cancel_job() {
  std::lock_guard lock(mutex_);
  if (job_.state != JobState::kRendering) return false;
  job_.state = JobState::kCancelled;
  job_.message = "cancelled";
  return true;
}

std::string RenderSession::render_error() const {
  std::lock_guard lock(mutex_);
  return error_version_ == view_.version ? render_error_ : std::string();
}

bool RenderSession::stopped() const {
  std::lock_guard lock(mutex_);
  return stop_;
}

double RenderSession::predicted_frame_seconds(const ViewSettings& s) const {
  return same_cost(s, measured_for_) ? full_frame_seconds_ : 0.0;
}

RenderJob RenderSession::job() const {
  std::lock_guard lock(mutex_);
  return job_;
}

SessionCounters RenderSession::counters() const {
  std::lock_guard lock(mutex_);
  return counters_;
}

void RenderSession::run() {
  Progress p;
  for (;;) {
    Step step;
    {
      std::unique_lock lock(mutex_);
      if (!wait_for_work(lock, p, step)) return;
    }
    try {
      if (step.kind == Step::Kind::kWriteJob) write_job(p);
      else render_step(step, p);
    } catch (const std::exception& e) { fail_step(step.view, p, e.what()); } catch (...) {
      fail_step(step.view, p, "unknown exception");
    }
  }
}

void RenderSession::fail_step(const View& view, Progress& p, const std::string& what) {
  p = Progress{};
  p.version = view.version;  // nothing more of this view until it changes
  p.complete = true;
  const std::string line = "live: the render of view " + std::to_string(view.version) + " (" +
                           std::to_string(view.settings.width) + "x" + std::to_string(view.settings.height) +
                           ") failed: " + what + "; it resumes at the next change";
  if (config_.log) config_.log(line);
  else std::fprintf(stderr, "%s\n", line.c_str());
  {
    std::lock_guard lock(mutex_);
    running_may_finish_ = false;
    render_error_ = what;
    error_version_ = view.version;
    ++failures_;
    if (job_.state == JobState::kRendering) {
      job_.state = JobState::kFailed;
      job_.message = "the render failed: " + what;
    }
    frame_cv_.notify_all();
  }
  if (config_.frames_changed) config_.frames_changed();
}

bool RenderSession::wait_for_work(std::unique_lock<std::mutex>& lock, const Progress& p, Step& step) {
  for (;;) {
    if (stop_) return false;
    const bool moving = Clock::now() < moving_until_;
    step.view = view_;
    step.changed_at = changed_at_;
    if (view_.version != p.version) {
      step.kind = Step::Kind::kRestart;
      step.divisor = moving ? preview_divisor(view_.settings.preview, predicted_frame_seconds(view_.settings),
                                              config_.frame_budget)
                            : 1;
      step.samples = 1;
      break;
    }
    if (p.divisor > 1 && !moving) {
      step.kind = Step::Kind::kRestart;
      step.divisor = 1;
      step.samples = 1;
      break;
    }
    if (p.divisor == 1 && !p.complete && !moving) {
      step.kind = Step::Kind::kContinue;
      step.divisor = 1;
      const double rate = same_cost(view_.settings, measured_for_) ? seconds_per_sample_ : 0.0;
      step.samples = next_step(p.done, uint32_t(view_.settings.samples), rate, config_.max_step_seconds);
      break;
    }
    if (p.divisor == 1 && p.complete && job_.state == JobState::kRendering && job_.view_version == p.version) {
      step.kind = Step::Kind::kWriteJob;
      return true;
    }
    // While the camera moves, the next move is awaited rather than more samples of this view.
    if (config_.on_idle) config_.on_idle();
    if (moving) work_cv_.wait_until(lock, moving_until_);
    else work_cv_.wait(lock);
  }
  // A view's first frame finishes even if the view changes meanwhile when it is expected within the
  // budget, or when the last one was cancelled: a camera that keeps moving keeps producing frames. Only
  // when its time is known (measured with the same size and settings) and at most max_uncancelled_seconds.
  const double predicted = predicted_frame_seconds(step.view.settings);
  const double expected = predicted / (double(step.divisor) * step.divisor);
  running_may_finish_ = step.kind == Step::Kind::kRestart && predicted > 0 &&
                        expected <= config_.max_uncancelled_seconds && (expected <= config_.frame_budget || starved_);
  cancel_.store(false);
  return true;
}

void RenderSession::render_step(const Step& step, Progress& p) {
  const ViewSettings& vs = step.view.settings;
  const bool restart = step.kind == Step::Kind::kRestart;
  const int width = preview_side(vs.width, step.divisor), height = preview_side(vs.height, step.divisor);
  const uint32_t first = restart ? 0 : p.done;
  RenderSettings rs = render_settings(config_.base, vs, width, height);
  rs.samples_per_pixel = int(first + step.samples);
  const Camera camera = resolve_camera(step.view.camera, width, height);

  Accumulation reached;
  std::atomic<uint64_t> chunks{0};
  std::atomic<double> fraction{0.0};
  RenderControl control;
  control.cancel = &cancel_;
  if (!restart) control.resume_from = &p.acc;
  control.on_pass = [&reached](const Accumulation& acc) { reached = acc; };
  control.progress = [&](double done) {  // after each chunk, on the thread that rendered it
    fraction.store(std::max(fraction.load(), done));
    uint64_t n = chunks.fetch_add(1) + 1;
    if (cancel_.load()) chunks_after_cancel_.fetch_add(1);
    if (config_.on_chunk) config_.on_chunk(n);
  };
  wf::WavefrontOptions options;
  options.wave_paths = std::max<size_t>(256, config_.wave_paths * 2 / (1 + size_t(vs.light_samples)));
  const Clock::time_point start = Clock::now();
  RenderOutput out = wf::render_wavefront(scene_, camera, rs, wf::Tracing{.bvh4 = &bvh_}, options, control);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();

  if (out.cancelled) {
    // A cancelled first frame still tells what a whole one costs with these settings.
    if (restart && fraction.load() > 0.0) {
      full_frame_seconds_ = seconds / fraction.load() * step.divisor * step.divisor;
      if (!same_cost(vs, measured_for_)) seconds_per_sample_ = 0;
      measured_for_ = vs;
    }
    std::lock_guard lock(mutex_);
    running_may_finish_ = false;
    ++counters_.passes_cancelled;
    starved_ = starved_ || restart;
    counters_.max_chunks_after_cancel = std::max(counters_.max_chunks_after_cancel, chunks_after_cancel_.load());
    counters_.last_cancel_seconds = std::chrono::duration<double>(Clock::now() - cancelled_at_).count();
    return;
  }
  // `p` and the measured rates belong to this thread; the lock guards what others read.
  if (restart) {
    p = Progress{};
    p.version = step.view.version;
    p.divisor = step.divisor;
    p.started = step.changed_at;
  }
  if (!reached.pixels.empty()) p.acc = std::move(reached);
  p.film = std::make_shared<const Film>(std::move(out.film));
  p.estimated_relative_rmse = out.error.available ? out.error.relative_rmse : -1.0;
  p.done = first + step.samples;
  p.rays += out.stats.rays();
  p.render_seconds += seconds;
  p.complete =
      p.done >= uint32_t(vs.samples) ||
      std::all_of(p.acc.pixels.begin(), p.acc.pixels.end(), [](const PixelAccumulator& a) { return a.converged != 0; });
  // The time of one sample at the view's size, from every render: it picks the preview's divisor.
  if (!same_cost(vs, measured_for_)) seconds_per_sample_ = 0;
  if (step.divisor == 1) seconds_per_sample_ = seconds / step.samples;
  full_frame_seconds_ = step.divisor == 1 ? seconds_per_sample_ : seconds * step.divisor * step.divisor;
  measured_for_ = vs;

  {
    std::lock_guard lock(mutex_);
    running_may_finish_ = false;
    if (job_.state == JobState::kRendering && job_.view_version == p.version && p.divisor == 1)
      job_.progress = double(p.done) / vs.samples;

    FrameInfo info;
    info.id = latest_ ? latest_->info.id + 1 : 1;
    info.view_version = p.version;
    info.width = width;
    info.height = height;
    info.view_width = vs.width;
    info.view_height = vs.height;
    info.samples = p.done;
    info.target = uint32_t(vs.samples);
    info.complete = p.complete && p.divisor == 1;
    info.seconds = std::chrono::duration<double>(Clock::now() - p.started).count();
    info.render_seconds = p.render_seconds;
    info.rays = p.rays;
    info.estimated_relative_rmse = p.estimated_relative_rmse;
    info.display = vs.display;
    info.camera = resolve_camera(step.view.camera, vs.width, vs.height);
    auto frame = std::make_shared<const Frame>(info, p.film, config_.quantization);
    starved_ = false;
    if (config_.on_frame) config_.on_frame(frame->info);
    latest_ = std::move(frame);
    ++counters_.frames;
    frame_cv_.notify_all();
  }
  if (config_.frames_changed) config_.frames_changed();
}

void RenderSession::write_job(const Progress& p) {
  std::filesystem::path path;
  bool adaptive = false, replace = true;
  {
    std::lock_guard lock(mutex_);
    path = job_.path;
    replace = job_.replace;
    adaptive = render_settings(config_.base, view_.settings, 1, 1).adaptive();
  }
  // The files are staged whole, then put in place only if the job still runs.
  std::string error;
  std::unique_ptr<StagedFile> image, rate;
  try {
    if (!p.film) throw InputError("nothing was rendered");
    image = std::make_unique<StagedFile>(path, encode_image(path, *p.film, config_.quantization));
    if (adaptive) rate = std::make_unique<StagedFile>(rate_image_path(path), encode_sample_rate_image(*p.film));
  } catch (const std::exception& e) { error = e.what(); }
  std::lock_guard lock(mutex_);
  if (job_.state != JobState::kRendering) return;  // cancelled: nothing is written
  if (error.empty()) {
    try {
      if (!image->publish(replace)) {
        error = path.string() + " exists (it is left as it is)";
      } else if (rate && !rate->publish(replace)) {
        error = rate->path().string() + " exists (it is left as it is)";
        std::filesystem::remove(path);  // the image just linked: the pair appears whole or not at all
      }
    } catch (const std::exception& e) { error = e.what(); }
  }
  image.reset();  // a staged file not put in place is removed before the job says how it ended
  rate.reset();
  job_.state = error.empty() ? JobState::kDone : JobState::kFailed;
  job_.progress = error.empty() ? 1.0 : job_.progress;
  job_.message = error;
}

}  // namespace pt::live
