// Stopping and resuming: an engine cancelled at a pass boundary or in the
// middle of a pass, then resumed from its saved state, gives the image of an
// uninterrupted render bit for bit; a checkpoint file round-trips and refuses
// a different render; the CLI writes a partial image on SIGINT (sent by its
// test hook after a given pass, never after a delay) and resumes.
#include <signal.h>

#include <atomic>
#include <cstring>
#include <fstream>

#include "io/camera_setup.h"
#include "io/checkpoint.h"
#include "io/scene_error.h"
#include "support/run_process.h"
#include "support/test_support.h"
#include "bvh/scene_bvh2.h"
#include "wavefront/engines.h"

namespace pt {
namespace {

struct Fixture {
  Scene scene = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  RenderSettings rs;
  Camera camera;
  SceneBvh2 accel{scene, Bvh2Mode::kMidpoint};
  Fixture() {
    rs.width = 40;
    rs.height = 30;
    rs.samples_per_pixel = 64;
    rs.max_depth = 4;
    rs.adaptive_batch = 8;
    rs.adaptive_tolerance = 0.1f;
    rs.threads = 2;
    camera = resolve_camera(scene, rs.width, rs.height);
  }
  RenderOutput render(const RenderControl& control) {
    return wf::render_wavefront(scene, camera, rs, wf::Tracing{.bvh2 = &accel}, {256}, control);
  }
};

void expect_same_film(const Film& a, const Film& b) {
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(float3)), 0);
  EXPECT_EQ(a.samples, b.samples);
}

TEST(Resume, FromAPassBoundaryEqualsAnUninterruptedRender) {
  Fixture f;
  Film full = f.render({}).film;
  std::atomic<bool> cancel{false};
  Accumulation saved;
  RenderControl stop;
  stop.cancel = &cancel;
  stop.on_pass = [&](const Accumulation& acc) {
    if (acc.samples_done == 16) {
      saved = acc;
      cancel = true;
    }
  };
  RenderOutput partial = f.render(stop);
  ASSERT_TRUE(partial.cancelled);
  ASSERT_EQ(saved.samples_done, 16u);
  RenderControl resume;
  resume.resume_from = &saved;
  expect_same_film(full, f.render(resume).film);
}

TEST(Resume, FromTheMiddleOfAPassEqualsAnUninterruptedRender) {
  Fixture f;
  f.rs.adaptive_tolerance = 0.0f;  // one pass of 64 samples, 300 chunks of 4 pixels
  Film full = f.render({}).film;
  std::atomic<bool> cancel{false};
  std::atomic<int> chunks{0};
  Accumulation saved;
  RenderControl stop;
  stop.cancel = &cancel;
  stop.progress = [&](double) {
    if (++chunks == 100) cancel = true;  // a third into the pass
  };
  stop.on_interrupt = [&](const Accumulation& acc) { saved = acc; };
  RenderOutput partial = f.render(stop);
  ASSERT_TRUE(partial.cancelled);
  ASSERT_FALSE(saved.pixels.empty());
  // Some pixels are ahead of the others: the interrupted pass was partly done.
  uint32_t lo = UINT32_MAX, hi = 0;
  for (const PixelAccumulator& p : saved.pixels)
    if (!p.converged) {
      lo = std::min(lo, p.samples);
      hi = std::max(hi, p.samples);
    }
  EXPECT_LT(lo, hi);
  RenderControl resume;
  resume.resume_from = &saved;
  expect_same_film(full, f.render(resume).film);
}

TEST(Checkpoint, RoundTripsAndRefusesADifferentRender) {
  Fixture f;
  Accumulation acc;
  acc.samples_done = 8;
  acc.pixels.resize(size_t(f.rs.width) * f.rs.height);
  acc.pixels[5].add({1, 2, 3});
  test::ScratchDir scratch;  // unique: test programs may run concurrently
  std::filesystem::path path = scratch / "checkpoint.bin";
  std::string fp = render_fingerprint("wavefront", f.scene, f.camera, f.rs);
  save_checkpoint(path, fp, acc);
  std::optional<Accumulation> back = load_checkpoint(path, fp, acc.pixels.size(), 64);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->samples_done, 8u);
  EXPECT_EQ(std::memcmp(back->pixels.data(), acc.pixels.data(), acc.pixels.size() * sizeof(PixelAccumulator)), 0);

  RenderSettings other = f.rs;
  other.seed = 99;
  EXPECT_THROW(load_checkpoint(path, render_fingerprint("wavefront", f.scene, f.camera, other), acc.pixels.size(), 64),
               InputError);
  EXPECT_THROW(load_checkpoint(path, fp, acc.pixels.size(), 4), InputError);  // more samples done than -s 4 takes
  {                                                                           // flip one byte: the checksum catches it
    std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(100);
    io.put('\x7f');
  }
  EXPECT_THROW(load_checkpoint(path, fp, acc.pixels.size(), 64), InputError);
  std::filesystem::remove(path);
  EXPECT_FALSE(load_checkpoint(path, fp, acc.pixels.size(), 64).has_value());
}

/// Runs the pathtracer with `args` and the extra `environment` ("NAME=VALUE").
test::ProcessResult run_pathtracer(const std::vector<std::string>& args,
                                   const std::vector<std::string>& environment = {}) {
  return test::run_process(PT_PATHTRACER_BINARY, args, std::filesystem::current_path(), 600.0, 0, environment);
}

// The render sends itself SIGINT after its first pass of 64 samples (the test hook
// PT_TEST_SIGINT_AFTER_PASS in cli/main.cpp), so the signal lands at the same point of
// the render on any machine: the stop handler, the partial image and the checkpoint are
// exercised every time, and resuming from that checkpoint gives the uninterrupted image.
TEST(CommandLine, SigintWritesAPartialImageAndTheCheckpointResumesExactly) {
  test::ScratchDir scratch;  // unique: test programs may run concurrently
  const std::filesystem::path dir = scratch.path();
  std::vector<std::string> common = {"--engine", "wavefront", "-t", "2",     "-s", "1024", "-m",
                                     "5",        "-a",        "64", "0.005", "-r", "96",   "72"};
  auto with = [&](std::vector<std::string> extra) {
    std::vector<std::string> a = common;
    a.insert(a.end(), extra.begin(), extra.end());
    return a;
  };
  std::string out = (dir / "img.png").string(), ck = (dir / "state.bin").string();
  test::ProcessResult full = run_pathtracer(with({"-q", "-f", (dir / "full.png").string()}));
  ASSERT_EQ(full.exit_code, 0) << full.err;

  test::ProcessResult stopped =
      run_pathtracer(with({"-q", "-f", out, "--checkpoint", ck}), {"PT_TEST_SIGINT_AFTER_PASS=1"});
  EXPECT_EQ(stopped.exit_code, 128 + SIGINT) << stopped.err;
  EXPECT_NE(stopped.err.find("interrupted: wrote the image so far to "), std::string::npos) << stopped.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "img.partial.png"));
  EXPECT_FALSE(std::filesystem::exists(out));
  ASSERT_TRUE(std::filesystem::exists(ck));

  test::ProcessResult resumed = run_pathtracer(with({"-f", out, "--checkpoint", ck}));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("(64 samples per pixel done)"), std::string::npos) << "resumed after the first pass:\n"
                                                                                << resumed.out;
  EXPECT_EQ(test::file_bytes(out), test::file_bytes(dir / "full.png"));
  EXPECT_EQ(test::file_bytes(dir / "img_rate.png"), test::file_bytes(dir / "full_rate.png"));
  EXPECT_FALSE(std::filesystem::exists(ck));  // removed once complete
}

}  // namespace
}  // namespace pt
