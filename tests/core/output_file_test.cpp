// check_writable and write_file_atomically: outputs are checked before the work, and a failed
// or interrupted write leaves the previous file as it was.
#include "slamkit/core/output_file.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "slamkit/core/error.h"

namespace slamkit {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("slamkit_output_file_" + std::to_string(::getpid())) / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t files_in(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
}

TEST(OutputFile, CheckWritableRejectsMissingDirectoriesAndDirectoriesAndLeavesNothing) {
  const fs::path dir = scratch("check");
  EXPECT_NO_THROW(check_writable((dir / "new.g2o").string(), "--output"));
  EXPECT_FALSE(fs::exists(dir / "new.g2o"));
  EXPECT_EQ(files_in(dir), 0u);
  EXPECT_NO_THROW(check_writable("-"));
  try {
    check_writable((dir / "no" / "such" / "out.g2o").string(), "--output");
    ADD_FAILURE() << "no error for a missing directory";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "no" / "such" / "out.g2o").string());
    EXPECT_EQ(e.field(), "--output");
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos) << e.what();
  }
  EXPECT_THROW(check_writable(dir.string()), InputError);
  EXPECT_THROW(check_writable(""), InputError);
}

TEST(OutputFile, ReplacesTheFileAndKeepsItsMode) {
  const fs::path dir = scratch("replace");
  const fs::path file = dir / "out.txt";
  write_file_atomically(file.string(), "first\n");
  EXPECT_EQ(slurp(file), "first\n");
  ::chmod(file.c_str(), 0640);
  write_file_atomically(file.string(), "second\n");
  EXPECT_EQ(slurp(file), "second\n");
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0640u);
  EXPECT_EQ(files_in(dir), 1u);  // no temporary file left
  EXPECT_THROW(write_file_atomically((dir / "missing" / "x").string(), "x"), InputError);
  EXPECT_THROW(write_file_atomically(dir.string(), "x"), InputError);
}

// A full disk, simulated by a file-size limit (RLIMIT_FSIZE, with SIGXFSZ ignored so write(2)
// fails with EFBIG): the write fails with a message, the old file is intact, no temporary is left.
TEST(OutputFile, AFailedWriteKeepsThePreviousFile) {
  const fs::path dir = scratch("full");
  const fs::path file = dir / "out.txt";
  write_file_atomically(file.string(), "the good old content\n");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    try {
      write_file_atomically(file.string(), std::string(1 << 20, 'x'));
    } catch (const InputError& e) {
      const bool names_reason = std::string(e.what()).find("previous file kept") != std::string::npos;
      ::_exit(names_reason ? 42 : 2);
    }
    ::_exit(1);  // no error: the limit did not bite
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 42);
  EXPECT_EQ(slurp(file), "the good old content\n");
  EXPECT_EQ(files_in(dir), 1u);
}

// Killed while writing (SIGKILL at random moments of a large write): the file is always either
// the old one or the complete new one, never a part.
TEST(OutputFile, AKilledWriterNeverLeavesHalfAFile) {
  const fs::path dir = scratch("killed");
  const fs::path file = dir / "out.txt";
  const std::string old_text = "old\n";
  const std::string new_text(64 << 20, 'n');
  write_file_atomically(file.string(), old_text);
  int replaced = 0;
  for (int attempt = 0; attempt < 8; ++attempt) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      write_file_atomically(file.string(), new_text);
      ::_exit(0);
    }
    ::usleep(static_cast<useconds_t>(2000) << attempt);  // 2 ms … 256 ms
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    const auto size = fs::file_size(file);
    ASSERT_TRUE(size == old_text.size() || size == new_text.size()) << "partial file of " << size << " bytes";
    if (size == new_text.size()) {
      ++replaced;
      write_file_atomically(file.string(), old_text);
    }
  }
  for (const auto& entry : fs::directory_iterator(dir))  // killed writers may leave their temporaries
    if (entry.path() != file) fs::remove(entry.path());
  std::cout << "[ note ] " << replaced << " of 8 killed writers had finished\n";
}

}  // namespace
}  // namespace slamkit
