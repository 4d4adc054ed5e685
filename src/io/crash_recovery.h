// What a killed run leaves behind, and how the next run cleans it up. Writers name their
// temporary siblings after their process: a folder DIR is staged as DIR.partial-PID and, where
// the file system cannot exchange two folders atomically, set aside as DIR.old-PID while the new
// one moves in; a file PATH is written as PATH.tmp-PID-RANDOM and renamed over PATH.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "ndfmip/result.h"

namespace ndfmip {

// Whether process `pid` may still be the writer of a leftover last modified at `modified`
// (seconds since the epoch): it exists, is not this process, and did not start after that
// moment (which would make it a later process that reuses the number).
bool writerMayBeAlive(long pid, int64_t modified);

// Cleans up beside `dir`: DIR.partial-PID and DIR.old-PID of writers that are gone are removed,
// except that when DIR itself is missing the newest such DIR.old-PID is renamed back to DIR.
void recoverFolderLeftovers(const std::filesystem::path& dir);

// Removes PATH.tmp-PID-* files beside `path` whose writer is gone.
void removeStaleTemporaries(const std::filesystem::path& path);

// Puts the finished folder `staging` in the place of `dir` (which may not exist). With
// `exchange`, an existing dir is swapped with staging in one atomic renameat2(RENAME_EXCHANGE),
// so dir is at every instant either the complete old folder or the complete new one; where the
// file system refuses that (or without `exchange`), dir is renamed to DIR.old-PID and staging to
// dir, a window that recoverFolderLeftovers closes after a kill. The earlier folder is then
// removed. Folders are synced so the swap survives a power cut too.
Status replaceFolder(const std::filesystem::path& staging, const std::filesystem::path& dir,
                     bool exchange = true);

// The folder a writer publishes as `name`: normalised, without a trailing separator.
std::filesystem::path folderPath(const std::string& name);

// Writes the folder `name` as a whole: its parent must exist; leftovers of killed runs are
// cleaned (recoverFolderLeftovers); an existing folder is replaced only when `replaceable` says
// so, asked before and again at the end (files may appear meanwhile); `fill` writes into a fresh
// DIR.partial-PID, which replaceFolder then puts in place. Any failure removes the staging folder
// and leaves the folder as it was. Messages about the folder itself start with `name`.
Status writeFolderWhole(const std::string& name,
                        const std::function<Status(const std::filesystem::path& dir)>& replaceable,
                        const std::function<Status(const std::filesystem::path& staging)>& fill);

} // namespace ndfmip
