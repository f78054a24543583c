// acuity::io (acuity/file.hpp), the offline libraries' one file seam: every refusal names the path
// and what is wrong, reads are bounded and confined, outputs are regular files never over an input,
// writes are atomic.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

#include "acuity/file.hpp"

#include "scratch_dir.hpp"

namespace fs = std::filesystem;
using namespace acuity;

namespace {

using acuity::testing::scratch;

fs::path write(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
  return p;
}

// The io::Error `f` throws (path and reason), or a failure when it throws none.
io::Error error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const io::Error& e) { return e; }
  ADD_FAILURE() << "no io::Error";
  return io::Error("", "no error");
}

int temporaries(const fs::path& dir) {
  int n = 0;
  for (const auto& e : fs::directory_iterator(dir))
    n += e.path().filename().string().find(".tmp.") != std::string::npos;
  return n;
}

}  // namespace

TEST(IoError, WhatIsPathThenReason) {
  const io::Error e("a/b.glb", "is a FIFO, not a regular file");
  EXPECT_EQ(e.path(), "a/b.glb");
  EXPECT_EQ(e.reason(), "is a FIFO, not a regular file");
  EXPECT_STREQ(e.what(), "a/b.glb: is a FIFO, not a regular file");
  EXPECT_STREQ(io::Error("", "the output path is empty").what(), "the output path is empty");
}

TEST(ReadFile, ReadsARegularFileWhole) {
  const fs::path p = write(scratch("read/seven.bin"), "1234567");
  const Blob b = io::read_file(p.string());
  ASSERT_EQ(b.size, 7u);
  EXPECT_EQ(std::string(static_cast<const char*>(b.data()), b.size), "1234567");
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(b.data()) % 8, 0u);  // what open_profile needs
  std::vector<unsigned char> bytes;
  io::read_file(p.string(), {}, &bytes);
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), "1234567");
  EXPECT_EQ(io::check_input(p.string()), 7u);
  EXPECT_EQ(io::read_file(write(scratch("read/empty.bin"), "").string()).size, 0u);
}

TEST(ReadFile, MissingDirectoryAndFifoAreRefusedByName) {
  const std::string missing = scratch("read/missing.bin").string();
  io::Error e = error_of([&] { io::read_file(missing); });
  EXPECT_EQ(e.path(), missing);
  EXPECT_EQ(e.reason(), "No such file or directory");
  const std::string dir = scratch("read/dir").string();
  fs::create_directories(dir);
  e = error_of([&] { io::read_file(dir); });
  EXPECT_EQ(e.path(), dir);
  EXPECT_EQ(e.reason(), "is a directory, not a regular file");
  const fs::path fifo = scratch("read/fifo");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  e = error_of([&] { io::read_file(fifo.string()); });  // returns at once: opened non-blocking
  EXPECT_EQ(e.reason(), "is a FIFO, not a regular file");
  EXPECT_EQ(error_of([&] { io::check_input(fifo.string()); }).reason(), "is a FIFO, not a regular file");
  e = error_of([&] { io::read_file("/dev/null"); });
  EXPECT_EQ(e.reason(), "is a device, not a regular file");
}

TEST(ReadFile, TooLargeIsRefusedBeforeReadingNamingTheLimit) {
  const fs::path p = write(scratch("read/hundred.bin"), std::string(100, 'x'));
  io::ReadLimits limits;
  limits.max_bytes = 99;
  limits.max_bytes_name = "the load limit max_file_bytes";
  EXPECT_STREQ(error_of([&] { io::read_file(p.string(), limits); }).what(),
               (p.string() + ": 100 bytes, more than the load limit max_file_bytes (99)").c_str());
  EXPECT_EQ(error_of([&] { io::check_input(p.string(), limits); }).reason(),
            "100 bytes, more than the load limit max_file_bytes (99)");
  limits.max_bytes = 100;  // the limit itself is allowed
  EXPECT_EQ(io::read_file(p.string(), limits).size, 100u);
}

TEST(ReadFile, ConfinedToItsRoot) {
  const fs::path root = scratch("root/assets"), secret = write(scratch("root/secret.bin"), "secret");
  write(root / "in.bin", "inside");
  fs::create_directories(root / "sub");
  fs::create_symlink(secret, root / "out_link.bin");
  fs::create_symlink(root / "in.bin", root / "sub" / "in_link.bin");
  io::ReadLimits limits;
  limits.root = root.string();
  EXPECT_EQ(io::read_file((root / "in.bin").string(), limits).size, 6u);
  EXPECT_EQ(io::read_file((root / "sub" / "in_link.bin").string(), limits).size, 6u);  // a link that stays in
  const std::string canonical_root = fs::canonical(root).string();
  for (const fs::path& p : {root / "out_link.bin", root / ".." / "secret.bin", secret}) {
    const io::Error e = error_of([&] { io::read_file(p.string(), limits); });
    EXPECT_EQ(e.path(), p.string());
    EXPECT_EQ(e.reason(), "leads outside the folder " + canonical_root + " (a symbolic link?)");
  }
  EXPECT_EQ(io::confine((root / "sub" / ".." / "in.bin").string(), root.string()),
            (fs::canonical(root) / "in.bin").string());
  EXPECT_NE(error_of([&] { io::confine(root.string(), root.string()); }).reason().find("leads outside"),
            std::string::npos);  // the folder itself is not a file inside it
}

TEST(CheckOutput, RefusesAnInputAndNonRegularFiles) {
  const fs::path in = write(scratch("out/in.glb"), "x"), hard = scratch("out/hard.glb");
  fs::create_hard_link(in, hard);
  for (const fs::path& out : {in, hard, scratch("out/./in.glb")}) {
    const io::Error e = error_of([&] { io::check_output(out.string(), {in.string()}); });
    EXPECT_EQ(e.path(), out.string());
    EXPECT_EQ(e.reason(), "is the input " + in.string() + "; refusing to overwrite an input");
  }
  const fs::path fifo = scratch("out/fifo.glb"), link = scratch("out/link.glb"), dir = scratch("out/dir.glb");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_symlink(scratch("out/new.glb"), link);
  fs::create_directories(dir);
  EXPECT_EQ(error_of([&] { io::check_output(fifo.string(), {}); }).reason(),
            "is a FIFO, not a regular file; refusing to replace it");
  EXPECT_EQ(error_of([&] { io::check_output(link.string(), {}); }).reason(),
            "is a symbolic link, not a regular file; refusing to replace it");
  EXPECT_EQ(error_of([&] { io::check_output(dir.string(), {}); }).reason(),
            "is a directory, not a regular file; refusing to replace it");
  EXPECT_EQ(error_of([&] { io::check_output("/dev/null", {}); }).reason(),
            "is a device, not a regular file; refusing to replace it");
}

TEST(CheckOutput, FolderAndExtension) {
  const fs::path nowhere = scratch("out2") / "no" / "such" / "x.glb";  // scratch() makes only out2's parent
  EXPECT_EQ(error_of([&] { io::check_output(nowhere.string(), {}); }).reason(),
            "its folder " + nowhere.parent_path().string() + " does not exist");
  EXPECT_EQ(error_of([&] {
              io::check_output(scratch("out2/x.off").string(), {}, {".glb", ".gltf"});
            }).reason(),
            "the output must end in .glb, .gltf");
  EXPECT_STREQ(error_of([&] { io::check_output("", {}); }).what(), "the output path is empty");
  EXPECT_NO_THROW(
      io::check_output(scratch("out2/fresh.GLB").string(), {scratch("out2/in.off").string()}, {".glb"}));
  write(scratch("out2/old.glb"), "old");
  EXPECT_NO_THROW(io::check_output(scratch("out2/old.glb").string(), {}));  // a regular file is replaced
}

TEST(CheckOutputFolder, MustBeOrLieInAWritableDirectory) {
  const fs::path file = write(scratch("folder/file"), "x");
  const io::Error e = error_of([&] { io::check_output_folder((file / "sub").string()); });
  EXPECT_EQ(e.path(), (file / "sub").string());
  EXPECT_EQ(e.reason(), file.string() + " exists and is not a directory");
  EXPECT_NO_THROW(io::check_output_folder((scratch("folder") / "new" / "deeper").string()));  // created later
  EXPECT_NO_THROW(io::check_output_folder(""));                                               // no output
}

TEST(WriteFileAtomically, ReplacesWholeAndLeavesNoTemporary) {
  const fs::path dir = scratch("write"), p = dir / "a.bin";
  fs::create_directories(dir);
  io::write_file_atomically(p.string(), "first");
  io::write_file_atomically(p.string(), "second, longer");
  EXPECT_EQ(io::read_file(p.string()).size, 14u);
  EXPECT_EQ((fs::status(p).permissions() & fs::perms::all), fs::perms(0644));
  EXPECT_EQ(temporaries(dir), 0);
  const fs::path fifo = dir / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const io::Error e = error_of([&] { io::write_file_atomically(fifo.string(), "x"); });
  EXPECT_EQ(e.path(), fifo.string());
  EXPECT_EQ(e.reason(), "is a FIFO, not a regular file; refusing to replace it");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));  // still the FIFO
  const fs::path missing = dir / "no" / "b.bin";
  EXPECT_NE(error_of([&] { io::write_file_atomically(missing.string(), "x"); }).reason().find("temporary"),
            std::string::npos);
  EXPECT_EQ(temporaries(dir), 0);
}

TEST(LowerExtension, LowerCaseWithTheDot) {
  EXPECT_EQ(io::lower_extension("a/B.GLB"), ".glb");
  EXPECT_EQ(io::lower_extension("x.tar.Gz"), ".gz");
  EXPECT_EQ(io::lower_extension("dir.d/none"), "");
  EXPECT_EQ(io::lower_extension(".hidden"), "");
}

TEST(ReadFileStatus, TheKeptFormReportsTheSameError) {
  Blob b;
  std::string error;
  EXPECT_FALSE(read_file(scratch("status/missing").string(), &b, &error));
  EXPECT_EQ(error, scratch("status/missing").string() + ": No such file or directory");
  EXPECT_TRUE(read_file(write(scratch("status/ok"), "ok").string(), &b, &error));
  EXPECT_EQ(b.size, 2u);
}
