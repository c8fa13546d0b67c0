// The journal keeps a run's finished blocks for --resume, and only that run's: blocks carry the
// run's identity, the manifest records who made the journal, and a live run holds a lock.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "formula/k_formula.hpp"
#include "model/run_spec.hpp"
#include "parallel/journal.hpp"
#include "parallel/journal_writer.hpp"
#include "parallel/run_identity.hpp"
#include "support/private_temp_dir.hpp"

namespace cs {
namespace {

namespace fs = std::filesystem;

class JournalTest : public ::testing::Test {
 protected:
  void SetUp() override {
    // A fresh private directory (mkdtemp): a guessable name in a shared /tmp may be another
    // user's, and the test removes its directory at the end.
    temp_ = std::make_unique<test::PrivateTempDir>("contactsweep_journal_");
    dir_ = temp_->path();
    fs::create_directories(dir_);
    output_ = (dir_ / "out.h5").string();
  }
  void TearDown() override { temp_.reset(); }

  static std::vector<ColumnSpec> columns() {
    DatasetSpec final_q, traj_q;
    final_q.name = "final_q";
    traj_q.name = "traj_q";
    return {{final_q, 1}, {traj_q, 3}};
  }
  static BlockResults block(std::int64_t begin, std::int64_t end, double seed) {
    BlockResults b({begin, end}, columns());
    for (auto& column : b.columns)
      for (std::size_t i = 0; i < column.size(); ++i) column[i] = seed + static_cast<double>(i);
    return b;
  }
  JournalManifest manifest(const std::string& run_id) const {
    return {run_id, build_identity(), 100, 10, false, "[scene]\nname = \"double_well\"\n"};
  }

  std::unique_ptr<test::PrivateTempDir> temp_;
  fs::path dir_;
  std::string output_;
};

TEST_F(JournalTest, SavedBlockComesBackBitForBit) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  const BlockResults saved = block(10, 20, 0.1);
  journal.save(saved);
  BlockResults loaded({10, 20}, columns());
  ASSERT_TRUE(journal.load(loaded));
  EXPECT_EQ(loaded.columns, saved.columns);
}

// The writer saves from its own thread what many threads hand it: every block comes back bit
// for bit, and on_saved counts 1, 2, ... n, each after that many blocks are in place.
TEST_F(JournalTest, WriterSavesEveryBlockHandedToItFromManyThreads) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  constexpr int kThreads = 4, kPerThread = 6, kBlocks = kThreads * kPerThread;
  std::vector<std::unique_ptr<BlockResults>> blocks;
  for (int b = 0; b < kBlocks; ++b)
    blocks.push_back(std::make_unique<BlockResults>(block(10 * b, 10 * b + 10, 0.5 * b)));
  std::vector<std::int64_t> reported;
  std::vector<std::int64_t> files_when_reported;
  int failures = 0;
  {
    JournalWriter writer(
        journal,
        [&](std::int64_t n) {
          reported.push_back(n);
          std::int64_t files = 0;
          for (const auto& entry : fs::directory_iterator(journal.directory()))
            files += entry.path().extension() == ".bin";
          files_when_reported.push_back(files);
        },
        [&] { ++failures; });
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        for (int k = 0; k < kPerThread; ++k) writer.submit(*blocks[t * kPerThread + k]);
      });
    for (auto& thread : threads) thread.join();
    writer.finish();
  }
  ASSERT_EQ(reported.size(), static_cast<std::size_t>(kBlocks));
  for (int n = 1; n <= kBlocks; ++n) {
    EXPECT_EQ(reported[n - 1], n);
    EXPECT_EQ(files_when_reported[n - 1], n) << "block " << n << " reported before it was in place";
  }
  EXPECT_EQ(failures, 0);
  for (const auto& saved : blocks) {
    BlockResults loaded(saved->range, columns());
    ASSERT_TRUE(journal.load(loaded));
    EXPECT_EQ(loaded.columns, saved->columns);
  }
}

// A failed save is reported once, saves nothing after it, never blocks a submitting thread, and
// finish() rethrows it with the reason.
TEST_F(JournalTest, WriterFailureIsReportedOnceAndRethrown) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  fs::remove_all(journal.directory());  // every save now fails: no directory to write in
  std::vector<std::unique_ptr<BlockResults>> blocks;
  for (int b = 0; b < 12; ++b)
    blocks.push_back(std::make_unique<BlockResults>(block(10 * b, 10 * b + 10, 1.0)));
  int saved = 0, failures = 0;
  JournalWriter writer(journal, [&](std::int64_t) { ++saved; }, [&] { ++failures; });
  for (const auto& b : blocks) writer.submit(*b);  // more than the queue holds: must not hang
  try {
    writer.finish();
    ADD_FAILURE() << "finish() did not rethrow the failed save";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot create"), std::string::npos) << e.what();
  }
  EXPECT_EQ(saved, 0);
  EXPECT_EQ(failures, 1);
}

TEST_F(JournalTest, BlockOfAnotherRunIsNeverLoaded) {
  {
    Journal a(output_, "00000000000000aa");
    a.lock();
    a.start(manifest("00000000000000aa"));
    a.save(block(0, 10, 1.0));
  }
  Journal b(output_, "00000000000000bb");
  BlockResults loaded({0, 10}, columns());
  EXPECT_FALSE(b.load(loaded));
}

TEST_F(JournalTest, DamagedOrMismatchedBlockIsComputedAgain) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  journal.save(block(0, 10, 1.0));
  BlockResults other_range({0, 11}, columns());
  EXPECT_FALSE(journal.load(other_range));
  const std::string path = journal.directory() + "/block_0.bin";
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(60);
    f.put('\x7f');  // the second column's size field (the payload starts at 64)
  }
  BlockResults loaded({0, 10}, columns());
  EXPECT_FALSE(journal.load(loaded));
}

// Bits flipped inside the payload, the file's size and every field before the payload intact:
// only the checksum can tell, and it must refuse every one (first, middle and last byte of each
// column, low and high bit). Columns of every kind the journal carries: float64 with and without
// a time axis, the int8 and uint8 labels, an internal column. After each flip the good bytes are
// put back and the block loads again, so it is the flip that was refused.
TEST_F(JournalTest, ChecksumRefusesAnyPayloadByteFlipped) {
  DatasetSpec final_q, traj_q, status, basin, settled;
  final_q.name = "final_q";
  traj_q.name = "traj_q";
  traj_q.has_time_dim = true;
  status.name = "status";
  status.type = ElementType::int8;
  basin.name = "basin";
  basin.type = ElementType::uint8;
  settled.name = "settle_point";
  const std::vector<ColumnSpec> specs = {
      {final_q, 1}, {traj_q, 4}, {status, 1}, {basin, 1}, {settled, 2, true}};
  constexpr std::int64_t kBegin = 30, kEnd = 47;
  BlockResults saved({kBegin, kEnd}, specs);
  for (std::size_t c = 0; c < saved.columns.size(); ++c)
    for (std::size_t i = 0; i < saved.columns[c].size(); ++i)
      saved.columns[c][i] = c == 2 || c == 3 ? static_cast<double>((i + c) % 3)
                                             : 0.1 * static_cast<double>(c) - 1.7 / (1.0 + i);
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  journal.save(saved);
  const std::string path = journal.directory() + "/block_30.bin";
  std::string good;
  {
    std::ifstream in(path, std::ios::binary);
    good.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  // magic, run id, (begin, end, columns), one size per column; then the payload; then the sum.
  std::size_t offset = 8 + 16 + 3 * 8 + 8 * specs.size();
  std::size_t payload_bytes = 0;
  for (const auto& col : saved.columns) payload_bytes += col.size() * sizeof(double);
  ASSERT_EQ(good.size(), offset + payload_bytes + 8);
  auto write = [&](const std::string& bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << bytes;
  };
  auto loads = [&] {  // load() alone: the checksum must refuse, not a comparison of values here
    BlockResults loaded({kBegin, kEnd}, specs);
    return journal.load(loaded);
  };
  auto loads_as_saved = [&] {
    BlockResults loaded({kBegin, kEnd}, specs);
    return journal.load(loaded) && loaded.columns == saved.columns;
  };
  ASSERT_TRUE(loads_as_saved());
  int flips = 0;
  for (std::size_t c = 0; c < saved.columns.size(); ++c) {
    const std::size_t bytes = saved.columns[c].size() * sizeof(double);
    for (std::size_t at : {offset, offset + bytes / 2 + 3, offset + bytes - 1}) {
      for (unsigned char bit : {0x01, 0x80}) {
        std::string bad = good;
        bad[at] = static_cast<char>(bad[at] ^ bit);
        write(bad);
        ASSERT_EQ(fs::file_size(path), good.size());
        EXPECT_FALSE(loads()) << "column " << c << ", byte " << at << ", bit " << int(bit);
        write(good);
        ASSERT_TRUE(loads_as_saved()) << "column " << c;
        ++flips;
      }
    }
    offset += bytes;
  }
  EXPECT_EQ(flips, 5 * 3 * 2);
  std::string bad = good;  // the stored sum itself
  bad[good.size() - 5] = static_cast<char>(bad[good.size() - 5] ^ 0x10);
  write(bad);
  EXPECT_FALSE(loads());
}

// A block whose settlement records grew as it ran (engine/settlement_records.hpp: one record of
// 2 dof + 1 values per distinct settled point, in a column that starts empty) comes back whole
// into a fresh block whose column is empty, as --resume makes it: a few records, and as many as
// the journal allows (one record of the widest system, 2 * kMaxFormulaDof + 1 values, for every
// point). Measured from the empty column, the load refused it and --resume silently computed
// every finished block of a basin map again.
TEST_F(JournalTest, GrownRecordsColumnComesBackIntoAnEmptyOne) {
  DatasetSpec basin, records;
  basin.name = "basin";
  basin.type = ElementType::int8;
  records.name = "basin_records";
  const std::vector<ColumnSpec> specs = {{basin, 1}, {records, 3, true, false, true}};
  constexpr std::int64_t kBegin = 40, kEnd = 56, kPoints = kEnd - kBegin;
  const std::size_t most = static_cast<std::size_t>(kPoints) * (2 * kMaxFormulaDof + 1);
  for (const std::size_t values : {std::size_t{3 * 5}, most}) {
    BlockResults saved({kBegin, kEnd}, specs);
    ASSERT_TRUE(saved.columns[1].empty());  // it starts empty: the kernel appends records
    for (std::size_t i = 0; i < saved.columns[0].size(); ++i) saved.columns[0][i] = double(i % 6);
    for (std::size_t i = 0; i < values; ++i) saved.columns[1].push_back(0.25 * double(i) - 3.0);
    Journal journal(output_, "00000000000000aa");
    journal.lock();
    journal.start(manifest("00000000000000aa"));
    journal.save(saved);
    BlockResults loaded({kBegin, kEnd}, specs);
    ASSERT_TRUE(loaded.columns[1].empty());
    ASSERT_TRUE(journal.load(loaded)) << values << " record values";
    EXPECT_EQ(loaded.columns[1].size(), values);
    EXPECT_EQ(loaded.columns, saved.columns);
  }
}

TEST_F(JournalTest, ManifestRecordsTheRunExactly) {
  Journal journal(output_, "0123456789abcdef");
  journal.lock();
  JournalManifest m = manifest("0123456789abcdef");
  m.replaces_output = true;
  m.spec_text = "title = \"two\nlines\"\n";
  journal.start(m);
  journal.save(block(0, 10, 1.0));
  const JournalContents c = journal.inspect();
  ASSERT_TRUE(c.manifest) << c.manifest_problem;
  EXPECT_EQ(c.manifest->run_id, m.run_id);
  EXPECT_EQ(c.manifest->build, build_identity());
  EXPECT_EQ(c.manifest->points, 100);
  EXPECT_EQ(c.manifest->block_size, 10);
  EXPECT_TRUE(c.manifest->replaces_output);
  EXPECT_EQ(c.manifest->spec_text, m.spec_text);
  EXPECT_EQ(c.block_files, 1);
}

TEST_F(JournalTest, OldFormatAndDamagedManifestsAreNamed) {
  fs::create_directories(output_ + ".journal");
  std::ofstream(output_ + ".journal/manifest") << "contactsweep journal\nversion 0.1.0\n";
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  JournalContents c = journal.inspect();
  EXPECT_FALSE(c.manifest);
  EXPECT_NE(c.manifest_problem.find("older contactsweep"), std::string::npos);
  std::ofstream(output_ + ".journal/manifest") << "contactsweep journal 2\nrun 12\n";
  c = journal.inspect();
  EXPECT_FALSE(c.manifest);
  EXPECT_NE(c.manifest_problem.find("damaged"), std::string::npos);
}

// Open-file-description locks conflict between two opens even within one process, so a second
// Journal here stands for a second run.
TEST_F(JournalTest, SecondRunIsRefusedWhileTheFirstHoldsTheLock) {
  Journal first(output_, "00000000000000aa");
  first.lock();
  Journal second(output_, "00000000000000bb");
  try {
    second.lock();
    FAIL() << "a second run took the lock";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("another run is writing this output"), std::string::npos) << message;
    EXPECT_NE(message.find("pid " + std::to_string(::getpid())), std::string::npos) << message;
  }
}

TEST_F(JournalTest, LockOfAFinishedRunIsFree) {
  {
    Journal first(output_, "00000000000000aa");
    first.lock();
    first.start(manifest("00000000000000aa"));
  }  // the process "ended": its lock is released, its journal stays
  EXPECT_TRUE(fs::exists(output_ + ".journal/manifest"));
  Journal second(output_, "00000000000000aa");
  EXPECT_NO_THROW(second.lock());
}

TEST_F(JournalTest, StartDropsAnEarlierRunAndRemoveLeavesNothing) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  journal.save(block(0, 10, 1.0));
  journal.start(manifest("00000000000000aa"));
  EXPECT_EQ(journal.inspect().block_files, 0);
  EXPECT_TRUE(fs::exists(journal.directory() + "/lock"));  // still held
  journal.remove();
  EXPECT_FALSE(fs::exists(journal.directory()));
}

// A run killed while it wrote block 0 and the manifest leaves their temporaries behind (written,
// not yet renamed). Resumed, the run computes block 0 again: its save must replace the stale
// temporary (which it once refused: "cannot create ...tmp: File exists", a resume that could not
// finish), and the block then loads. A fresh start clears such debris too, and removing the
// finished journal leaves no directory behind.
TEST_F(JournalTest, TemporariesOfAKilledWriterAreReplacedAndCleared) {
  Journal journal(output_, "00000000000000aa");
  journal.lock();
  journal.start(manifest("00000000000000aa"));
  const std::string block_tmp = journal.directory() + "/block_0.bin.tmp";
  const std::string manifest_tmp = journal.directory() + "/manifest.tmp";
  std::ofstream(block_tmp) << "half a block";
  std::ofstream(manifest_tmp) << "contactsweep journal 2\nrun";
  const BlockResults saved = block(0, 10, 2.5);
  ASSERT_NO_THROW(journal.save(saved));
  EXPECT_FALSE(fs::exists(block_tmp));
  BlockResults loaded({0, 10}, columns());
  ASSERT_TRUE(journal.load(loaded));
  EXPECT_EQ(loaded.columns, saved.columns);

  std::ofstream(block_tmp) << "half a block";
  std::ofstream(journal.directory() + "/block_20.bin.tmp") << "half a block";
  journal.start(manifest("00000000000000aa"));  // --force: everything of the earlier run goes
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(journal.directory()))
    left.push_back(entry.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"lock", "manifest"}));
  std::ofstream(journal.directory() + "/block_30.bin.tmp") << "half a block";
  journal.remove();
  EXPECT_FALSE(fs::exists(journal.directory()));
}

TEST_F(JournalTest, RunRefusedBeforeItStartedLeavesNoDirectory) {
  {
    Journal journal(output_, "00000000000000aa");
    journal.lock();
  }
  EXPECT_FALSE(fs::exists(output_ + ".journal"));
}

TEST(RunIdentity, DependsOnSpecPointsAndBlocks) {
  const std::string id = run_identity("a = 1\n", 100, 10);
  EXPECT_EQ(id.size(), 16u);
  EXPECT_EQ(id, run_identity("a = 1\n", 100, 10));
  EXPECT_NE(id, run_identity("a = 2\n", 100, 10));
  EXPECT_NE(id, run_identity("a = 1\n", 101, 10));
  EXPECT_NE(id, run_identity("a = 1\n", 100, 11));
}

TEST(RunIdentity, BuildIsTheExecutablesBuildId) {
  // The linker's note (CMake asks for --build-id); the fallback hash would say exe-fnv1a.
  EXPECT_NE(build_identity().find("build-id "), std::string::npos) << build_identity();
}

}  // namespace
}  // namespace cs
