// The output policy (gimg/geometry/atomic_file.h): regular files only, whole or not at all, and
// the files of an OutputSet together.
#include "gimg/geometry/atomic_file.h"
#include "gimg/geometry/error.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using gimg::geo::create_output_folder;
using gimg::geo::InputError;
using gimg::geo::OutputSet;
using gimg::geo::write_file_atomically;

namespace {

fs::path fresh_folder(const std::string& name) {
    const fs::path dir = fs::path(GIMG_TEST_OUTPUT_DIR) / "output_files" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

std::string read(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

std::size_t entries(const fs::path& dir) {
    std::size_t n = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
    return n;
}

}  // namespace

TEST(OutputFiles, ReplacesRegularFilesAndRefusesEverythingElse) {
    const fs::path dir = fresh_folder("targets");
    write_file_atomically(dir / "a.txt", "one");
    write_file_atomically(dir / "a.txt", "two");
    EXPECT_EQ(read(dir / "a.txt"), "two");

    fs::create_symlink(dir / "a.txt", dir / "link.txt");
    EXPECT_THROW(write_file_atomically(dir / "link.txt", "three"), InputError);
    EXPECT_TRUE(fs::is_symlink(dir / "link.txt"));
    EXPECT_EQ(read(dir / "a.txt"), "two");

    ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0600), 0);
    EXPECT_THROW(write_file_atomically(dir / "pipe", "x"), InputError);
    EXPECT_TRUE(fs::is_fifo(dir / "pipe"));

    fs::create_directory(dir / "folder");
    EXPECT_THROW(write_file_atomically(dir / "folder", "x"), InputError);
    EXPECT_THROW(write_file_atomically(dir / "missing" / "b.txt", "x"), InputError);
    EXPECT_EQ(entries(dir), 4u);  // a.txt, link.txt, pipe, folder: no temporary file left
}

TEST(OutputFiles, ASetAppearsAtCommitOrNotAtAll) {
    const fs::path dir = fresh_folder("sets");
    write_file_atomically(dir / "old.txt", "old");
    {
        OutputSet set;
        write_file_atomically(dir / "new.txt", "new");
        write_file_atomically(dir / "old.txt", "replaced");
        EXPECT_FALSE(fs::exists(dir / "new.txt"));  // only temporary files so far
        EXPECT_EQ(read(dir / "old.txt"), "old");
    }  // abandoned: nothing changes
    EXPECT_FALSE(fs::exists(dir / "new.txt"));
    EXPECT_EQ(read(dir / "old.txt"), "old");
    EXPECT_EQ(entries(dir), 1u);
    {
        OutputSet outer;
        {
            OutputSet inner;  // hands its files to the outer set
            write_file_atomically(dir / "inner.txt", "inner");
            inner.commit();
        }
        write_file_atomically(dir / "new.txt", "new");
        EXPECT_FALSE(fs::exists(dir / "inner.txt"));
        outer.commit();
    }
    EXPECT_EQ(read(dir / "inner.txt"), "inner");
    EXPECT_EQ(read(dir / "new.txt"), "new");
    EXPECT_EQ(entries(dir), 3u);
}

TEST(OutputFiles, TemporaryFilesOfDeadProcessesAreRemovedOnTheNextWrite) {
    const fs::path dir = fresh_folder("stale");
    // A pid that is not running (beyond Linux's pid_max) and this process's own.
    std::ofstream(dir / ".a.txt.gimg-999999999-0.tmp") << "stale";
    const fs::path mine = dir / (".a.txt.gimg-" + std::to_string(::getpid()) + "-77.tmp");
    std::ofstream(mine) << "in flight";
    write_file_atomically(dir / "a.txt", "fresh");
    EXPECT_FALSE(fs::exists(dir / ".a.txt.gimg-999999999-0.tmp"));
    EXPECT_TRUE(fs::exists(mine));  // a running process's file is left alone
    EXPECT_EQ(read(dir / "a.txt"), "fresh");
}

TEST(OutputFiles, AnAbandonedSetRemovesTheEmptyFoldersMadeForIt) {
    const fs::path dir = fresh_folder("folders");
    fs::create_directory(dir / "there");
    {
        OutputSet set;
        EXPECT_FALSE(create_output_folder(dir / "there" / "a" / "b"));
        EXPECT_FALSE(create_output_folder(dir / "c"));
        EXPECT_FALSE(create_output_folder(dir / "d"));
        std::ofstream(dir / "d" / "not_ours.txt") << "kept";  // written outside gimg's policy
        EXPECT_TRUE(fs::is_directory(dir / "there" / "a" / "b"));
    }
    EXPECT_FALSE(fs::exists(dir / "there" / "a"));
    EXPECT_FALSE(fs::exists(dir / "c"));
    EXPECT_TRUE(fs::is_directory(dir / "there"));  // it was there before
    EXPECT_TRUE(fs::exists(dir / "d" / "not_ours.txt"));
    {
        OutputSet outer;
        {
            OutputSet inner;  // hands its folder to the outer set, which commits
            EXPECT_FALSE(create_output_folder(dir / "e" / "f"));
            inner.commit();
        }
        outer.commit();
    }
    EXPECT_TRUE(fs::is_directory(dir / "e" / "f"));
    {
        OutputSet outer;
        {
            OutputSet inner;  // committed into a set that then fails
            EXPECT_FALSE(create_output_folder(dir / "g"));
            write_file_atomically(dir / "g" / "x.txt", "x");
            inner.commit();
        }
    }
    EXPECT_FALSE(fs::exists(dir / "g"));
    std::ofstream(dir / "file") << "a file";
    EXPECT_TRUE(create_output_folder(dir / "file" / "sub"));
}
