// Where nmdp may write an output, and how: one rule for every command that writes files.
//
// An output never replaces
//  - an input of the same run. Paths are compared by file identity (device and inode, symbolic
//    links followed), so a symlink, a hard link or another spelling ("./x", "a/../x") of an input is
//    that input;
//  - an existing file that is not an nmdp output, nor anything that is not a regular file (a
//    folder, a device such as /dev/null, a pipe). nmdp outputs are recognised by their marker:
//    HDF5 files carry the root attribute `nmdp_output` (every HDF5 file nmdp writes), or one of
//    the markers of files written before it existed: `nmdp_model` (model files), `nmdp_dataset`
//    (force datasets), or the root attribute `config` together with the dataset /status
//    (trajectories). An HTML page (nmdp view) carries kPageMarkerPrefix in its first kilobyte,
//    e.g. <meta name="nmdp-output" content="view">. A folder of CSV files written by `nmdp gen-rft` holds kFolderMarker, the list
//    of the files it wrote; an existing folder is written into only if it is empty or holds nothing
//    but those files.
// Every refusal is one InputError naming the output and what it would replace.
//
// Files are built under a unique temporary name in the destination folder
// ("<name>.<16 hex digits>.partial", created exclusively) and renamed onto the final name once
// complete, so a reader never sees half a file, an existing output is replaced only by a complete
// one, and two runs writing into one folder never share a temporary file.
#pragma once
#include <string>
#include <vector>

namespace nmdp {

struct RunInput {
  std::string path;  // as the user gave it (used in the message)
  std::string role;  // what it is to the run, e.g. "the scene", "the URDF", "--data"
};

// The regular files directly in `folder` (a folder input such as a CSV dataset), each with `role`;
// nothing if it is not a folder.
std::vector<RunInput> filesInFolder(const std::string& folder, const std::string& role);

// Throws InputError unless `output` may be written (see above): it does not exist, or it is a
// regular file that is an nmdp output and none of `inputs`. Its folder must exist. `option` names
// where the output path came from in the message, e.g. "--out".
void checkOutputFile(const std::string& output, const std::vector<RunInput>& inputs, const std::string& option);

// The same for an output folder that will receive the files `names`: it may not exist yet (it is
// created), or be an empty folder, or hold only files listed in its kFolderMarker; and none of the
// files it will receive may be one of `inputs`.
void checkOutputFolder(const std::string& folder, const std::vector<std::string>& names,
                       const std::vector<RunInput>& inputs, const std::string& option);

// The marker file of an output folder: JSON {"nmdp_output": "<command>", "files": [names]}.
inline constexpr const char* kFolderMarker = "nmdp_output.json";
// Writes the marker of `folder` listing `names` (before the files themselves, so that a folder
// interrupted half-way is still recognised as nmdp's).
void writeFolderMarker(const std::string& folder, const std::string& command, const std::vector<std::string>& names);

// The start of the marker element of a page nmdp wrote.
inline constexpr const char* kPageMarkerPrefix = "<meta name=\"nmdp-output\"";

// Whether `path` is an existing HDF5 file carrying one of the nmdp markers above, or a marked page.
bool isNmdpOutputFile(const std::string& path);

// A name in the folder of `final_path` that does not exist yet: "<name>.<16 hex digits>.partial".
// The caller creates it exclusively (O_EXCL, H5F_ACC_EXCL) and retries with a new name if that fails
// because it exists.
std::string temporaryPathFor(const std::string& final_path);

// Writes `content` to a temporary file beside `path` and renames it onto `path`. InputError naming
// `path` on failure (the temporary file is removed).
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace nmdp
