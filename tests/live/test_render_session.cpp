// The render session against the engine it drives: a still view at N
// samples is the wavefront's own -s N render bit for bit (whatever steps it
// took: with adaptive sampling, several light samples, hemisphere sampling,
// normal shading), a change restarts it, a change cancels the running pass
// within one wave, tabs share one render, and the Render job writes the view.
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <cstring>
#include <thread>

#include <gtest/gtest.h>

#include "bvh/scene_bvh4.h"
#include "io/image_output.h"
#include "live/render_session.h"
#include "support/http_probe.h"
#include "support/run_process.h"
#include "support/test_support.h"
#include "wavefront/engines.h"

namespace pt::live {
namespace {

using std::chrono::milliseconds;
constexpr int kW = 48, kH = 36;

struct Cornell {
  LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  SceneBvh4 bvh{loaded.scene};
  const Scene& scene() const { return loaded.scene; }
};
const Cornell& cornell() {
  static const Cornell c;
  return c;
}

SessionConfig config(int samples) {
  const Scene& s = cornell().scene();
  SessionConfig c;
  c.base.width = kW;
  c.base.height = kH;
  c.base.threads = 2;
  c.base.max_depth = 3;
  c.base.seed = 5;
  c.base.samples_per_pixel = samples;
  c.settings = view_settings_of(c.base);
  c.limits = nav_limits(s.bounds);
  c.camera = view_from_camera(resolve_camera(s, kW, kH), kW, kH, s.bounds.center(), c.limits);
  c.still_after = milliseconds(0);
  // Steps of 1, 3, 9... samples whatever the machine's speed: the cap by measured time
  // (test_progressive.cpp) would split them on a loaded machine or under the sanitizers.
  c.max_step_seconds = 1e9;
  return c;
}

/// The first complete frame of view `version` (or later).
std::shared_ptr<const Frame> complete_frame(const RenderSession& session, uint64_t version) {
  uint64_t after = 0;
  for (int i = 0; i < 2000; ++i) {
    std::shared_ptr<const Frame> f = session.frame_after(after, milliseconds(10000));
    if (!f) break;
    after = f->info.id;
    if (f->info.view_version >= version && f->info.complete) return f;
  }
  ADD_FAILURE() << "no complete frame";
  return nullptr;
}

/// The engine's own render of the session's current view.
RenderOutput engine_render(const RenderSession& session) {
  RenderSession::View v = session.view();
  RenderSettings rs = render_settings(session.config().base, v.settings, v.settings.width, v.settings.height);
  Camera c = resolve_camera(v.camera, v.settings.width, v.settings.height);
  return wf::render_wavefront(cornell().scene(), c, rs, wf::Tracing{.bvh4 = &cornell().bvh});
}

/// The frame's pixels equal the engine film's PNG values; the job's PFM (if any) its floats.
void expect_frame_is_render(const Frame& f, const RenderOutput& r, uint32_t samples) {
  EXPECT_EQ(f.info.samples, samples);
  EXPECT_EQ(f.info.width, r.film.width);
  EXPECT_EQ(film_rgba(r.film, f.info.display, ChannelEncoder(PngQuantization::kNearest), f.info.target), f.rgba());
}

struct Variant {
  const char* name;
  std::function<void(ViewSettings&)> change;
};

class StillView : public ::testing::TestWithParam<Variant> {};

TEST_P(StillView, AtNSamplesIsTheEnginesRenderOfNSamplesBitForBit) {
  SessionConfig c = config(13);  // steps of 1, 3 and 9 samples: no pass boundary of a 13-sample render
  GetParam().change(c.settings);
  RenderSession session(cornell().scene(), cornell().bvh, c);
  std::shared_ptr<const Frame> f = complete_frame(session, 1);
  ASSERT_TRUE(f);
  RenderOutput r = engine_render(session);
  expect_frame_is_render(*f, r, *std::max_element(r.film.samples.begin(), r.film.samples.end()));
  // The frame carries the render's own error estimate, the one render of 13 samples makes.
  ASSERT_TRUE(r.error.available);
  EXPECT_EQ(f->info.estimated_relative_rmse, r.error.relative_rmse);
  // The Render job writes the same film: its floats.
  test::ScratchDir dir;
  ASSERT_EQ(session.start_job(dir / "view.pfm"), "");
  for (int i = 0; i < 500 && session.job().state == JobState::kRendering; ++i)
    std::this_thread::sleep_for(milliseconds(10));
  ASSERT_EQ(session.job().state, JobState::kDone) << session.job().message;
  int w = 0, h = 0;
  std::vector<float3> written = read_pfm(dir / "view.pfm", w, h);
  ASSERT_EQ(written.size(), r.film.radiance.size());
  EXPECT_EQ(std::memcmp(written.data(), r.film.radiance.data(), written.size() * sizeof(float3)), 0);
}

INSTANTIATE_TEST_SUITE_P(Settings, StillView,
                         ::testing::Values(Variant{"Default", [](ViewSettings&) {}},
                                           Variant{"AdaptiveSampling",
                                                   [](ViewSettings& s) {
                                                     s.adaptive_tolerance = 0.2f;
                                                     s.adaptive_batch = 4;
                                                   }},
                                           Variant{"FourLightSamplesIndirectOnly",
                                                   [](ViewSettings& s) {
                                                     s.light_samples = 4;
                                                     s.bounces = BounceMode::kIndirectOnly;
                                                   }},
                                           Variant{"Hemisphere",
                                                   [](ViewSettings& s) { s.direct = DirectLighting::kHemisphere; }},
                                           Variant{"Normals", [](ViewSettings& s) { s.display = Display::kNormals; }},
                                           Variant{"SampleRate",
                                                   [](ViewSettings& s) {
                                                     s.display = Display::kSampleRate;
                                                     s.adaptive_tolerance = 0.2f;
                                                     s.adaptive_batch = 4;
                                                   }}),
                         [](const auto& info) { return std::string(info.param.name); });

/// Every frame the session publishes (width, samples, version), in order, and how many times its render
/// thread has had nothing to do.
struct FrameLog {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<FrameInfo> frames;
  size_t idles = 0;           ///< times the render thread started waiting for a change
  size_t frames_at_idle = 0;  ///< frames published when it last did
  void attach(SessionConfig& c) {
    c.on_frame = [this](const FrameInfo& f) {
      std::lock_guard lock(mutex);
      frames.push_back(f);
    };
    c.on_idle = [this] {
      {
        std::lock_guard lock(mutex);
        ++idles;
        frames_at_idle = frames.size();
      }
      changed.notify_all();
    };
  }
  /// Waits until the render thread has nothing to do after publishing `frame_count` frames in all: it will
  /// render nothing more until something changes. False if that does not come within a minute (a timeout).
  bool idle_after(size_t frame_count) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, std::chrono::seconds(60), [&] { return idles > 0 && frames_at_idle >= frame_count; });
  }
  size_t count() {
    std::lock_guard lock(mutex);
    return frames.size();
  }
  std::vector<FrameInfo> of_version(uint64_t v) {
    std::lock_guard lock(mutex);
    std::vector<FrameInfo> out;
    for (const FrameInfo& f : frames)
      if (f.view_version == v) out.push_back(f);
    return out;
  }
};

TEST(RenderSession, ACameraMoveRestartsTheViewFromItsFirstSample) {
  FrameLog log;
  SessionConfig c = config(8);
  log.attach(c);
  RenderSession session(cornell().scene(), cornell().bvh, c);
  ASSERT_TRUE(complete_frame(session, 1));
  const uint64_t v = session.navigate({NavInput::Kind::kOrbit, 40.0, -15.0});
  std::shared_ptr<const Frame> f = complete_frame(session, v);
  ASSERT_TRUE(f);
  std::vector<uint32_t> samples;
  for (const FrameInfo& i : log.of_version(v)) samples.push_back(i.samples);
  EXPECT_EQ(samples, (std::vector<uint32_t>{1, 4, 8}));
  expect_frame_is_render(*f, engine_render(session), 8);
  // A reset returns to the first view exactly.
  session.navigate({NavInput::Kind::kReset});
  const ViewCamera reset = session.view().camera;
  EXPECT_EQ(std::memcmp(&reset, &session.config().camera, sizeof(ViewCamera)), 0);
}

/// The session an on_chunk callback acts on. The session's render thread starts in its
/// constructor, so a callback can run before the test has the session's address: it waits for it.
class SessionSlot {
 public:
  void set(RenderSession& session) { session_.store(&session); }
  RenderSession& get() const {
    RenderSession* s;
    while (!(s = session_.load())) std::this_thread::yield();
    return *s;
  }

 private:
  std::atomic<RenderSession*> session_{nullptr};
};

TEST(RenderSession, AChangeCancelsTheRunningPassWithinOneWave) {
  SessionConfig c = config(16);  // steps of 1, 3 and 12 samples
  c.settings.width = c.base.width = 64;
  c.settings.height = c.base.height = 48;
  c.wave_paths = 256;    // 3072 pixels: 12 chunks per sample, each checked for the cancel
  c.frame_budget = 0.0;  // no frame is short enough to be let finish
  SessionSlot self;
  std::atomic<int> step_chunks{0};
  std::atomic<bool> moved{false};
  c.on_chunk = [&](uint64_t chunk) {
    // In the third step (12 samples x 12 chunks), move the camera at its 5th chunk.
    if (chunk == 5 && step_chunks.fetch_add(1) == 2 && !moved.exchange(true))
      self.get().navigate({NavInput::Kind::kOrbit, 5.0, 0.0});
  };
  RenderSession session(cornell().scene(), cornell().bvh, c);
  self.set(session);
  ASSERT_TRUE(complete_frame(session, 2));
  SessionCounters n = session.counters();
  EXPECT_TRUE(moved.load());
  EXPECT_EQ(n.passes_cancelled, 1u);
  // After the cancel only the chunks already running finish: at most one per thread.
  EXPECT_LE(n.max_chunks_after_cancel, uint64_t(c.base.threads));
}

/// Counts the cancels of a session whose on_chunk moves the camera at the third chunk of the first render
/// after arm() (64x48 with 12 chunks per sample), so that the passes it cancels can be counted.
struct MoveAtThirdChunk {
  RenderSession* session = nullptr;
  std::atomic<bool> armed{false}, moved{false};
  explicit MoveAtThirdChunk(SessionConfig& c) {
    c.settings.width = c.base.width = 64;
    c.settings.height = c.base.height = 48;
    c.wave_paths = 256;
    c.on_chunk = [this](uint64_t chunk) {
      if (chunk == 3 && armed.load() && !moved.exchange(true)) session->navigate({NavInput::Kind::kOrbit, 5.0, 0.0});
    };
  }
};

TEST(RenderSession, AFirstFrameAfterASizeChangeIsNotExpectedAtTheOldSizesCostSoAMoveCancelsIt) {
  SessionConfig c = config(4);
  MoveAtThirdChunk mover(c);
  c.frame_budget = 1e9;  // every frame measured so far is within the budget: let finish, were it not for the change
  c.max_uncancelled_seconds = 1e9;
  RenderSession session(cornell().scene(), cornell().bvh, c);
  mover.session = &session;
  ASSERT_TRUE(complete_frame(session, 1));
  ViewSettings bigger = session.view().settings;
  bigger.width = 128;  // four times the pixels, whose cost nothing measured yet
  bigger.height = 96;
  mover.armed.store(true);
  const uint64_t resized = session.set_settings(bigger);
  ASSERT_TRUE(complete_frame(session, resized + 1));
  EXPECT_TRUE(mover.moved.load());
  SessionCounters n = session.counters();
  EXPECT_EQ(n.passes_cancelled, 1u) << "the resized view's first frame was let finish after the move";
  EXPECT_LE(n.max_chunks_after_cancel, uint64_t(c.base.threads));
}

TEST(RenderSession, AFirstFrameExpectedBeyondTheCapIsCancelledEvenWithinTheBudget) {
  SessionConfig c = config(4);
  MoveAtThirdChunk mover(c);
  c.frame_budget = 1e9;
  c.max_uncancelled_seconds = 0.0;  // no frame is short enough to run uncancelled
  RenderSession session(cornell().scene(), cornell().bvh, c);
  mover.session = &session;
  ASSERT_TRUE(complete_frame(session, 1));
  mover.armed.store(true);
  const uint64_t moved = session.navigate({NavInput::Kind::kOrbit, -5.0, 0.0});
  ASSERT_TRUE(complete_frame(session, moved + 1));
  EXPECT_TRUE(mover.moved.load());
  SessionCounters n = session.counters();
  EXPECT_EQ(n.passes_cancelled, 1u);
  EXPECT_LE(n.max_chunks_after_cancel, uint64_t(c.base.threads));
}

TEST(RenderSession, AnExceptionInTheRenderIsLoggedReportedAndTheNextChangeRendersAgain) {
  SessionConfig c = config(4);
  std::mutex log_mutex;
  std::vector<std::string> log;
  c.log = [&](const std::string& line) {
    std::lock_guard lock(log_mutex);
    log.push_back(line);
  };
  std::atomic<bool> fail{false}, job_started{false};
  c.on_chunk = [&](uint64_t) {
    if (!fail.exchange(false)) return;
    for (int i = 0; i < 10000 && !job_started.load(); ++i) std::this_thread::sleep_for(milliseconds(1));
    throw std::bad_alloc();  // once the job below has started
  };
  RenderSession session(cornell().scene(), cornell().bvh, c);
  std::shared_ptr<const Frame> first = complete_frame(session, 1);
  ASSERT_TRUE(first);
  test::ScratchDir dir;
  fail.store(true);
  const uint64_t failed = session.navigate({NavInput::Kind::kOrbit, 5.0, 0.0});
  ASSERT_EQ(session.start_job(dir / "never.png"), "");
  job_started.store(true);
  // A frame request waiting meanwhile returns at the failure, not at the end of its wait: with a wait
  // of an hour, a request that only its timeout ended would hold the test until ctest's limit fails it.
  EXPECT_FALSE(session.frame_after(first->info.id, std::chrono::hours(1)));
  EXPECT_NE(session.render_error().find("bad_alloc"), std::string::npos) << session.render_error();
  EXPECT_EQ(session.job().state, JobState::kFailed);
  {
    std::lock_guard lock(log_mutex);
    ASSERT_EQ(log.size(), 1u);
    EXPECT_EQ(log[0].rfind("live: the render of view " + std::to_string(failed) + " ", 0), 0u) << log[0];
    EXPECT_NE(log[0].find("bad_alloc"), std::string::npos) << log[0];
  }
  // The failed view is not tried again in a loop, and a request made after the failure returns at once
  // (it waited its whole timeout when only a failure during the wait ended it); the next change renders.
  EXPECT_FALSE(session.frame_after(first->info.id, std::chrono::hours(1)));
  // A job asked for on the failed view is refused, not left waiting for a render that never comes.
  EXPECT_NE(session.start_job(dir / "never.png").find("bad_alloc"), std::string::npos);
  const uint64_t next = session.navigate({NavInput::Kind::kOrbit, 5.0, 0.0});
  ASSERT_TRUE(complete_frame(session, next));
  EXPECT_EQ(session.render_error(), "");
  EXPECT_TRUE(dir.entries().empty());
}

TEST(RenderSession, ACameraThatKeepsMovingKeepsProducingFramesEvenWhenTheyAreSlow) {
  FrameLog log;
  SessionConfig c = config(4);
  c.settings.width = c.base.width = 64;
  c.settings.height = c.base.height = 48;
  c.settings.preview = 1;  // full resolution while moving
  c.wave_paths = 256;      // 12 chunks per frame
  c.frame_budget = 0.0;    // no frame is expected within the budget
  c.still_after = milliseconds(60000);
  log.attach(c);
  SessionSlot self;
  std::atomic<int> moves{0};
  c.on_chunk = [&](uint64_t chunk) {  // a move during every render: each would cancel the frame under way
    if (chunk == 2 && moves.load() < 20 && moves.fetch_add(1) < 20)
      self.get().navigate({NavInput::Kind::kOrbit, 2.0, 0.0, true});
  };
  RenderSession session(cornell().scene(), cornell().bvh, c);
  self.set(session);
  while (moves.load() < 20) std::this_thread::sleep_for(milliseconds(1));
  const uint64_t last = session.navigate({NavInput::Kind::kPan, 1.0, 0.0});
  ASSERT_TRUE(complete_frame(session, last));
  size_t moving_frames = 0;
  for (uint64_t v = 2; v < last; ++v) moving_frames += log.of_version(v).size();
  // The first view's frame finishes; then every cancelled frame is followed by one that finishes.
  EXPECT_GE(moving_frames, 9u);
  EXPECT_LE(session.counters().passes_cancelled, 11u);
}

TEST(RenderSession, TabsShareOneRender) {
  // The second step (3 more samples) is held until both tabs have the first frame: both get that one.
  SessionConfig c = config(4);
  std::atomic<int> published{0}, received{0};
  c.on_frame = [&](const FrameInfo&) { published.fetch_add(1); };
  c.on_chunk = [&](uint64_t) {
    for (int i = 0; i < 10000 && published.load() == 1 && received.load() < 2; ++i)
      std::this_thread::sleep_for(milliseconds(1));
  };
  RenderSession session(cornell().scene(), cornell().bvh, c);
  std::shared_ptr<const Frame> a, b;
  std::thread t1([&] {
    a = session.frame_after(0, milliseconds(10000));
    received.fetch_add(1);
  });
  std::thread t2([&] {
    b = session.frame_after(0, milliseconds(10000));
    received.fetch_add(1);
  });
  t1.join();
  t2.join();
  ASSERT_TRUE(a && b);
  EXPECT_EQ(a->info.id, 1u);
  EXPECT_EQ(a.get(), b.get()) << "one frame object for both waiters";
  ASSERT_TRUE(complete_frame(session, 1));
  EXPECT_EQ(session.counters().frames, 2u) << "samples 1, 4: one render whoever watches";
  // A page from before a restart (its id beyond the newest) gets the newest at once.
  EXPECT_TRUE(session.frame_after(1000000, milliseconds(0)));
}

/// The frames of view `v`: a one-sample preview at half resolution while the
/// drag goes on, then from one sample again at full resolution, to -s.
void expect_preview_then_full(FrameLog& log, RenderSession& session, uint64_t v) {
  std::shared_ptr<const Frame> done = complete_frame(session, v);
  ASSERT_TRUE(done);
  std::vector<FrameInfo> frames = log.of_version(v);
  ASSERT_GE(frames.size(), 2u);
  EXPECT_EQ(frames[0].width, kW / 2);
  EXPECT_EQ(frames[0].height, kH / 2);
  EXPECT_EQ(frames[0].samples, 1u);
  EXPECT_FALSE(frames[0].complete);
  EXPECT_EQ(frames[1].width, kW);
  EXPECT_EQ(frames[1].samples, 1u);
  EXPECT_EQ(done->info.width, kW);
  expect_frame_is_render(*done, engine_render(session), 4);
}

TEST(RenderSession, ADragShowsPreviewsUntilItEnds) {
  FrameLog log;
  SessionConfig c = config(4);
  c.settings.preview = 2;
  c.still_after = milliseconds(60000);  // only the end of the drag ends the previews
  log.attach(c);
  RenderSession session(cornell().scene(), cornell().bvh, c);
  ASSERT_TRUE(complete_frame(session, 1));
  const uint64_t v = session.navigate({NavInput::Kind::kPan, 3.0, 1.0, true});
  // Once the preview is out, the render thread has nothing to do until the drag goes on or ends.
  ASSERT_TRUE(test::wait_until([&] { return !log.of_version(v).empty(); }));
  ASSERT_TRUE(log.idle_after(log.count()));
  EXPECT_EQ(log.of_version(v).size(), 1u) << "no samples beyond the preview while the drag goes on";
  EXPECT_EQ(session.navigate({NavInput::Kind::kStill}), v) << "the end of a drag changes no view";
  expect_preview_then_full(log, session, v);
}

TEST(RenderSession, ADragThatFallsSilentEndsAfterStillAfter) {
  FrameLog log;
  SessionConfig c = config(4);
  c.settings.preview = 2;
  c.still_after = milliseconds(300);
  log.attach(c);
  RenderSession session(cornell().scene(), cornell().bvh, c);
  ASSERT_TRUE(complete_frame(session, 1));
  expect_preview_then_full(log, session, session.navigate({NavInput::Kind::kOrbit, 3.0, 1.0, true}));
}

TEST(RenderSession, ADiscreteMoveAccumulatesAtOnce) {
  FrameLog log;
  SessionConfig c = config(4);
  c.settings.preview = 2;
  c.still_after = milliseconds(60000);
  log.attach(c);
  RenderSession session(cornell().scene(), cornell().bvh, c);
  ASSERT_TRUE(complete_frame(session, 1));
  const uint64_t v = session.navigate({NavInput::Kind::kZoom, -1.0});  // a key or a click: nothing follows
  ASSERT_TRUE(complete_frame(session, v));
  for (const FrameInfo& f : log.of_version(v)) EXPECT_EQ(f.width, kW);
}

/// A session whose render waits at every chunk while `hold` is set, with its frames logged.
struct HeldSession {
  std::atomic<bool> hold{true};
  FrameLog log;
  SessionConfig config;
  std::unique_ptr<RenderSession> session;
  explicit HeldSession(int samples) : config(live::config(samples)) {
    config.on_chunk = [this](uint64_t) {
      while (hold.load()) std::this_thread::sleep_for(milliseconds(1));
    };
    log.attach(config);
    session = std::make_unique<RenderSession>(cornell().scene(), cornell().bvh, config);
  }
};

TEST(RenderSession, AMoveCancelsTheRenderJobAndTheJobWritesNoFile) {
  HeldSession held(4);
  RenderSession& session = *held.session;
  test::ScratchDir dir;
  ASSERT_EQ(session.start_job(dir / "never.png"), "");
  EXPECT_NE(session.start_job(dir / "other.png"), "") << "one job at a time";
  const uint64_t moved = session.navigate({NavInput::Kind::kZoom, 1.0});
  EXPECT_EQ(session.job().state, JobState::kCancelled);
  EXPECT_EQ(session.job().message, "the view changed");
  held.hold.store(false);
  ASSERT_TRUE(complete_frame(session, moved));
  // The render thread writes a job's file before it has nothing more to do.
  ASSERT_TRUE(held.log.idle_after(held.log.count()));
  EXPECT_TRUE(dir.entries().empty());
}

TEST(RenderSession, ACancelledJobWritesNoFileWhenItsViewCompletes) {
  HeldSession held(4);
  RenderSession& session = *held.session;
  test::ScratchDir dir;
  ASSERT_EQ(session.start_job(dir / "never.png"), "");
  EXPECT_TRUE(session.cancel_job());
  EXPECT_EQ(session.job().state, JobState::kCancelled);
  held.hold.store(false);
  ASSERT_TRUE(complete_frame(session, 1));  // the job's view, complete: its file would be written now
  ASSERT_TRUE(held.log.idle_after(held.log.count()));
  EXPECT_EQ(session.job().state, JobState::kCancelled);
  EXPECT_TRUE(dir.entries().empty());
  // Not cancelled, the same job writes its file.
  ASSERT_EQ(session.start_job(dir / "kept.png"), "");
  ASSERT_TRUE(test::wait_until([&] { return session.job().state != JobState::kRendering; }));
  EXPECT_EQ(session.job().state, JobState::kDone);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"kept.png"}));
}

}  // namespace
}  // namespace pt::live
