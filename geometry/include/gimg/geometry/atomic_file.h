#pragma once
// gimg's output policy, for every file the library and the command line write:
//  - Only regular files are written. A target that exists and is not a regular file (a device, a
//    pipe, a folder or a symbolic link) is refused with geo::InputError, never replaced.
//  - A file is written whole to a temporary file beside it (".NAME.gimg-PID.tmp"), then renamed
//    over the target, so a reader never sees half a file. The temporary file is removed on any
//    error, on SIGINT and SIGTERM once remove_outputs_on_signals() is installed, and by the next
//    write of the same target when the process that left it is gone.
//  - Inside an OutputSet, the renames wait for commit(): a command's files appear together, after
//    every one of them was written, or none do. The folders create_output_folder() made for the
//    set go again, if still empty, when it is abandoned: a failed command leaves no empty folder.
//  - The disk failing (full, read-only, an I/O error) throws geo::EnvironmentError.

#include <filesystem>
#include <string_view>
#include <system_error>
#include <vector>

namespace gimg::geo {

// Throws InputError, naming the path, when `path` exists and is not a regular file or its folder
// does not exist.
void check_output_target(const std::filesystem::path& path);

// Checks the target, then writes `contents` by the policy above.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

// Creates `dir` and its missing parents; the error (none: empty) if it cannot. Inside an
// OutputSet, the folders it made are removed again, those still empty, if the set is abandoned.
std::error_code create_output_folder(const std::filesystem::path& dir);

// The files written on this thread while it is alive take their names together at commit(); if it
// is destroyed before, their temporary files are removed, no target changes and the folders made
// for it by create_output_folder go, where empty. Sets nest: an inner set hands its files and
// folders to the outer one.
class OutputSet {
public:
    OutputSet();
    ~OutputSet();
    OutputSet(const OutputSet&) = delete;
    OutputSet& operator=(const OutputSet&) = delete;
    void commit();
    // Called by write_file_atomically: `temp` becomes `target` at commit(); `slot` is its entry in
    // the signal handler's list.
    void add(std::filesystem::path temp, std::filesystem::path target, int slot);
    // Called by create_output_folder: a folder it made, removed (if empty) should the set fail.
    void add_folder(std::filesystem::path dir);

private:
    struct Pending {
        std::filesystem::path temp, target;
        int slot;
    };
    std::vector<Pending> files_;
    struct Folder {
        std::filesystem::path path;
        int slot;  // in the signal handler's list
    };
    std::vector<Folder> folders_;  // in the order made: parents first
    OutputSet* outer_;
    bool done_ = false;
};

// Installs SIGINT and SIGTERM handlers that remove every temporary file in flight, and the empty
// folders made for output sets, then end the process as the signal would have. For programs (the
// gimg command line); a library leaves the signals to its host.
void remove_outputs_on_signals();

}  // namespace gimg::geo
