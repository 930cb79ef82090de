// The live view's render: one thread renders the shared view (every tab sees
// the same one) progressively with the wavefront engine and publishes
// frames; HTTP handlers change the view and wait for frames, never render.
// A change restarts the view from its first sample: it cancels the running
// pass within one wave (RenderControl::cancel is checked per chunk of paths),
// except a view's first frame (one sample) that is expected within the frame
// budget or follows a cancelled one, which finishes, so that a moving camera
// keeps producing frames; while the camera moves, only such first frames are
// rendered, and accumulation resumes once it stops. The expectation is the
// measured time of a frame with the same size and settings (none after a
// change of either: then the frame can be cancelled), and a frame expected to
// take longer than max_uncancelled_seconds is never let finish. An exception in
// the render (a view too large for memory) is logged, stops that view's render
// until the next change, and is reported by render_error(). Samples accumulate in
// sample order from step to step (resume_from), so a still view at N samples
// is the image `pathtracer -s N` renders with the same camera and flags.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "bvh/scene_bvh4.h"
#include "camera_nav.h"
#include "frame_image.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"
#include "view_settings.h"

namespace pt::live {

struct SessionConfig {
  RenderSettings base;    ///< the command line's settings (sampler, seed, roulette, course quirks, threads)
  ViewSettings settings;  ///< the page's settings at the start
  ViewCamera camera;      ///< the camera at the start; a reset returns to it
  NavLimits limits;
  PngQuantization quantization = PngQuantization::kNearest;
  double frame_budget = 1.0 / 30;                  ///< seconds a frame may take while the camera moves
  double max_step_seconds = 0.25;                  ///< the longest progressive step of a still view
  double max_uncancelled_seconds = 0.25;           ///< the longest a frame that a change does not cancel may take
  std::chrono::milliseconds still_after{150};      ///< a drag without a move for this long has ended (without kStill)
  size_t wave_paths = 4096;                        ///< camera samples per wave at -l 1 (fewer for more light samples)
  std::function<void(uint64_t chunk)> on_chunk;    ///< tests: called after each chunk of paths (render threads)
  std::function<void(const FrameInfo&)> on_frame;  ///< tests: called as each frame is published (render thread)
  /// tests: called each time the render thread, with nothing to do, starts waiting for a change (render
  /// thread, under the session's lock: it must not call the session)
  std::function<void()> on_idle;
  std::function<void(const std::string&)> log;  ///< one line per render failure (none: stderr)
  /// called, outside the session's lock, whenever frame requests may have news: a frame, a failed render, the stop
  std::function<void()> frames_changed;
};

/// A camera move from the page, in pixels of the view (zoom: wheel steps).
/// kStill changes nothing but says the camera stopped (a drag ended).
struct NavInput {
  enum class Kind : uint8_t { kOrbit, kPan, kZoom, kReset, kStill };
  Kind kind = Kind::kOrbit;
  double dx = 0, dy = 0;  ///< orbit, pan: pixels; zoom: dx steps
  bool moving = false;    ///< more moves follow (a drag): preview frames until kStill or `still_after`
};

enum class JobState : uint8_t { kIdle, kRendering, kDone, kFailed, kCancelled };
inline constexpr const char* kJobStateNames[] = {"idle", "rendering", "done", "failed", "cancelled"};

/// The Render button's job: the view accumulated to -s, then written.
struct RenderJob {
  JobState state = JobState::kIdle;
  std::filesystem::path path;  ///< the PNG
  bool replace = true;         ///< false: a file of that name (or its _rate.png) fails the job instead
  uint64_t view_version = 0;   ///< the view it renders
  double progress = 0;         ///< samples done / -s
  std::string message;         ///< why it failed or was cancelled
};

struct SessionCounters {
  uint64_t frames = 0;                   ///< frames published
  uint64_t passes_cancelled = 0;         ///< renders stopped by a change
  uint64_t max_chunks_after_cancel = 0;  ///< the most chunks a cancelled render finished after its cancel
  double last_cancel_seconds = 0;        ///< from the last cancel to the end of the render it stopped
};

class RenderSession {
 public:
  /// Starts the render thread. `scene` and `bvh` outlive the session.
  RenderSession(const Scene& scene, const SceneBvh4& bvh, SessionConfig config);
  ~RenderSession();
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  struct View {
    ViewCamera camera;
    ViewSettings settings;
    uint64_t version = 0;           ///< of camera and settings: grows with every change
    uint64_t settings_version = 0;  ///< of the settings alone (pages resynchronise their controls)
  };
  View view() const;
  const SessionConfig& config() const { return config_; }

  /// Each change returns the new view version. Values must be valid (the
  /// request layer checks them).
  uint64_t navigate(const NavInput& in);
  uint64_t set_camera(const ViewCamera& camera);
  uint64_t set_settings(const ViewSettings& settings);

  /// The newest frame once its id exceeds `after` (at once if `after` is
  /// beyond the newest: a page from before a restart), else null after
  /// `timeout`, or at once when the session stops, a render fails meanwhile
  /// or the current view's render has failed already.
  std::shared_ptr<const Frame> frame_after(uint64_t after, std::chrono::milliseconds timeout) const;
  /// Why the current view's render failed, or "" (it renders, or rendered).
  std::string render_error() const;
  /// stop() was called: no frame will come.
  bool stopped() const;

  /// Starts the Render button's job for the current view: "" or why not. Its
  /// files appear whole, once the view has all its samples, and only if the job
  /// is still running then; with `replace` false, never over an existing file.
  std::string start_job(const std::filesystem::path& png, bool replace = true);
  /// Cancels a running job (the view keeps rendering); false when none runs.
  bool cancel_job();
  RenderJob job() const;
  SessionCounters counters() const;

  /// Stops the render thread (also on destruction); frame waiters return.
  void stop();

 private:
  struct Progress;
  struct Step;
  void run();
  bool wait_for_work(std::unique_lock<std::mutex>& lock, const Progress& p, Step& step);
  void render_step(const Step& step, Progress& p);
  void write_job(const Progress& p);
  /// After an exception in the step for `view`: log it, stop rendering the view until it changes, fail the job.
  void fail_step(const View& view, Progress& p, const std::string& what);
  /// full_frame_seconds_ when it was measured with settings of the same cost as `s`, else 0 (unknown).
  double predicted_frame_seconds(const ViewSettings& s) const;
  uint64_t changed();  ///< under the lock: bump the version, cancel what is stale

  const Scene& scene_;
  const SceneBvh4& bvh_;
  const SessionConfig config_;

  mutable std::mutex mutex_;
  std::condition_variable work_cv_;
  mutable std::condition_variable frame_cv_;
  View view_;
  std::chrono::steady_clock::time_point changed_at_;
  std::chrono::steady_clock::time_point moving_until_;  ///< a drag is under way until then
  std::shared_ptr<const Frame> latest_;
  RenderJob job_;
  SessionCounters counters_;
  bool stop_ = false;
  bool running_may_finish_ = false;  ///< the running render is a view's first frame that a change does not cancel
  bool starved_ = false;             ///< a view's first frame was cancelled since the last frame published
  double full_frame_seconds_ = 0;    ///< one sample per pixel at the view's size, as last measured (render thread)
  double seconds_per_sample_ = 0;    ///< the same, from the last full-resolution step (render thread)
  ViewSettings measured_for_;        ///< the settings of those measurements (render thread)
  std::string render_error_;         ///< why the render of view version error_version_ failed
  uint64_t error_version_ = 0;
  uint64_t failures_ = 0;  ///< renders failed (frame waiters return at each)

  std::atomic<bool> cancel_{false};
  std::atomic<uint64_t> chunks_after_cancel_{0};
  std::chrono::steady_clock::time_point cancelled_at_;
  std::thread thread_;
};

}  // namespace pt::live
