// Output files appear whole or not at all (io/atomic_file): exact contents,
// no temporary file left behind on success or failure (nor once published,
// while the staged file lives), a reader never sees a
// half-written replacement, a staged file published without replacing leaves
// an existing file alone, and check_writable() refuses what the write would
// refuse while leaving the directory as it was.
#include <atomic>
#include <fstream>
#include <thread>

#include <gtest/gtest.h>

#include "io/atomic_file.h"
#include "io/image_output.h"
#include "io/scene_error.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

TEST(AtomicFile, WritesExactBytesAndNothingElse) {
  test::ScratchDir dir;
  std::string bytes("binary\0data\n", 12);
  write_file_atomically(dir / "out.bin", bytes);
  EXPECT_EQ(test::file_bytes(dir / "out.bin"), bytes);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.bin"});
}

TEST(AtomicFile, AStagedFilePublishedWithoutReplacingLeavesAnExistingFileAlone) {
  test::ScratchDir dir;
  write_file_atomically(dir / "taken.txt", "mine");
  {
    StagedFile staged(dir / "taken.txt", "theirs");
    EXPECT_FALSE(staged.publish(false));
    StagedFile fresh(dir / "new.txt", "new");
    EXPECT_TRUE(fresh.publish(false));
  }
  EXPECT_EQ(test::file_bytes(dir / "taken.txt"), "mine");
  EXPECT_EQ(test::file_bytes(dir / "new.txt"), "new");
  { StagedFile unpublished(dir / "never.txt", "x"); }
  StagedFile replacing(dir / "taken.txt", "replaced");
  EXPECT_TRUE(replacing.publish(true));
  EXPECT_EQ(test::file_bytes(dir / "taken.txt"), "replaced");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"new.txt", "taken.txt"})) << "no temporary file is left";
}

// A caller may report a published file done before the StagedFile goes (the
// live view's render job does): by then no temporary name may be left.
TEST(AtomicFile, APublishedFileLeavesNoTemporaryNameWhileItsStagedFileLives) {
  test::ScratchDir dir;
  StagedFile linked(dir / "linked.txt", "a");
  ASSERT_TRUE(linked.publish(false));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"linked.txt"});
  StagedFile renamed(dir / "renamed.txt", "b");
  ASSERT_TRUE(renamed.publish(true));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"linked.txt", "renamed.txt"}));
  EXPECT_EQ(test::file_bytes(dir / "linked.txt"), "a");
}

TEST(AtomicFile, AReaderSeesTheOldOrTheNewFileNeverAMixture) {
  test::ScratchDir dir;
  const std::filesystem::path path = dir / "image.bin";
  const std::string a(1 << 20, 'a'), b(1 << 20, 'b');
  write_file_atomically(path, a);
  std::atomic<bool> done{false};
  std::atomic<int> reads{0}, torn{0};
  std::thread reader([&] {
    while (!done) {
      std::string seen = test::file_bytes(path);
      ++reads;
      if (seen != a && seen != b) ++torn;
    }
  });
  for (int i = 0; i < 40; ++i) write_file_atomically(path, i % 2 ? a : b);
  done = true;
  reader.join();
  EXPECT_GT(reads.load(), 0);
  EXPECT_EQ(torn.load(), 0) << "of " << reads.load() << " reads";
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"image.bin"});
}

TEST(AtomicFile, FailureThrowsNamingThePathAndLeavesNothing) {
  test::ScratchDir dir;
  std::filesystem::create_directory(dir / "sub");
  for (const std::filesystem::path& bad : {dir / "missing" / "out.png", dir / "sub"}) {
    SCOPED_TRACE(bad.string());
    try {
      write_file_atomically(bad, "data");
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) { EXPECT_EQ(std::string(e.what()).rfind(bad.string() + ": ", 0), 0u) << e.what(); }
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"sub"});
    EXPECT_TRUE(std::filesystem::is_empty(dir / "sub"));
  }
}

TEST(AtomicFile, CheckWritableRefusesWhatTheWriteWouldAndLeavesNothing) {
  test::ScratchDir dir;
  dir.write("file", "x");
  std::filesystem::create_directory(dir / "sub");
  EXPECT_NO_THROW(check_writable(dir / "new.png"));
  EXPECT_NO_THROW(check_writable(dir / "file"));  // replacing an existing file is fine
  EXPECT_THROW(check_writable(dir / "missing" / "out.png"), InputError);
  EXPECT_THROW(check_writable(dir / "file" / "out.png"), InputError);
  EXPECT_THROW(check_writable(dir / "sub"), InputError);
  EXPECT_THROW(check_writable(dir / "sub" / ""), InputError);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"file", "sub"}));
  EXPECT_EQ(test::file_bytes(dir / "file"), "x");
}

TEST(AtomicFile, ImagesAreWrittenThroughIt) {
  test::ScratchDir dir;
  Film film(3, 2, 1);
  for (size_t i = 0; i < film.radiance.size(); ++i) film.radiance[i] = float3(float(i), 0.5f, -1.0f);
  write_image(dir / "out.pfm", film);
  write_image(dir / "out.png", film);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"out.pfm", "out.png"}));
  int w = 0, h = 0;
  std::vector<float3> back = read_pfm(dir / "out.pfm", w, h);
  ASSERT_EQ(back.size(), film.radiance.size());
  for (size_t i = 0; i < back.size(); ++i) EXPECT_EQ(back[i], film.radiance[i]);
  EXPECT_EQ(test::file_bytes(dir / "out.png").substr(1, 3), "PNG");
}

}  // namespace
}  // namespace pt
