// Replays the fuzzer's committed inputs (test/fuzz/corpus: seeds; test/fuzz/corpus_grown: what a
// 30-minute run added, merged down to the inputs that keep its coverage; test/fuzz/crashes: the
// reproducers of every crash `make fuzz` found, kept after the fix) through the fuzz entry
// point, built with the normal compiler: a fixed crash that comes back fails `make test`.
#include <gtest/gtest.h>

#include <dirent.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz_entry.h"

namespace
{
using ohm_mirror_detector3d::fuzz::FuzzOutcome;
using ohm_mirror_detector3d::fuzz::runFuzzInput;

std::vector<std::string> filesIn(const std::string& folder)
{
  std::vector<std::string> files;
  if (DIR* dir = opendir(folder.c_str()))
  {
    while (const dirent* entry = readdir(dir))
    {
      const std::string name = entry->d_name;
      if (!name.empty() && name[0] != '.' && name != "README.md")
        files.push_back(folder + "/" + name);
    }
    closedir(dir);
  }
  std::sort(files.begin(), files.end());
  return files;
}

FuzzOutcome replay(const std::string& path)
{
  std::ifstream file(path, std::ios::binary);
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  return runFuzzInput(bytes.data(), bytes.size());
}

TEST(FuzzCorpus, EverySeedIsAValidSweepOfItsModeAndPassesTheInvariants)
{
  const std::vector<std::string> seeds = filesIn(OHM_FUZZ_DIR "/corpus");
  ASSERT_EQ(seeds.size(), 15u) << "five input modes x three parameter sets (make_seed_corpus.py)";
  for (const std::string& seed : seeds)
  {
    const FuzzOutcome outcome = replay(seed);
    // A seed that no longer converts would make the fuzzer start from rejected inputs only.
    EXPECT_TRUE(outcome.deserialized) << seed;
    EXPECT_TRUE(outcome.converted) << seed << ": " << outcome.problem;
    EXPECT_GE(outcome.sweeps, 1u) << seed;
  }
}

TEST(FuzzCorpus, GrownCorpusRunsCleanly)
{
  // Mostly malformed inputs: each must be refused or processed with the invariants intact
  // (runFuzzInput aborts otherwise).
  std::size_t converted = 0;
  const std::vector<std::string> inputs = filesIn(OHM_FUZZ_DIR "/corpus_grown");
  for (const std::string& input : inputs)
  {
    SCOPED_TRACE(input);
    converted += replay(input).converted ? 1 : 0;
  }
  std::printf("replayed %zu grown inputs, %zu of them accepted by their adapter\n", inputs.size(), converted);
}

TEST(FuzzCorpus, CrashReproducersRunCleanly)
{
  // runFuzzInput aborts on a broken invariant; sanitizers are off here, but a crash, an
  // exception or an abort still fails the test.
  for (const std::string& reproducer : filesIn(OHM_FUZZ_DIR "/crashes"))
  {
    SCOPED_TRACE(reproducer);
    replay(reproducer);
  }
}

}  // namespace
