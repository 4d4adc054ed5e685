// What a killed run leaves behind, and how the next run cleans it up. Writers name their
// temporary siblings after themselves (TAG = PID-TID-N, writerTag): a folder DIR is staged as
// DIR.partial-TAG and, where the file system cannot exchange two folders atomically, set aside
// as DIR.old-TAG while the new one moves in; a file PATH is written as PATH.tmp-TAG-RANDOM and
// renamed over PATH. A leftover is stale only once the process of its PID is gone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "ndfmip/result.h"

namespace ndfmip {

// "PID-TID-N": this process, this thread and a count of the names made in this process, so
// that no two writers (threads of one process included) ever share a temporary name.
std::string writerTag();

// Whether process `pid` may still be the writer of a leftover last modified at `modified`
// (seconds since the epoch): it exists (this process included: another of its threads may be
// writing) and did not start after that moment (which would make it a later process that
// reuses the number).
bool writerMayBeAlive(long pid, int64_t modified);

// Cleans up beside `dir`: DIR.partial-TAG and DIR.old-TAG of writers that are gone are removed,
// except that when DIR itself is missing the newest such DIR.old-TAG is renamed back to DIR.
void recoverFolderLeftovers(const std::filesystem::path& dir);

// Removes PATH.tmp-PID-* files beside `path` whose writer is gone.
void removeStaleTemporaries(const std::filesystem::path& path);

// Puts the finished folder `staging` in the place of `dir` (which may not exist). With
// `exchange`, an existing dir is swapped with staging in one atomic renameat2(RENAME_EXCHANGE),
// so dir is at every instant either the complete old folder or the complete new one; where the
// file system refuses that (or without `exchange`), dir is renamed to DIR.old-TAG and staging to
// dir, a window that recoverFolderLeftovers closes after a kill. The earlier folder is then
// removed. Folders are synced so the swap survives a power cut too.
Status replaceFolder(const std::filesystem::path& staging, const std::filesystem::path& dir,
                     bool exchange = true);

// The folder a writer publishes as `name`: normalised, without a trailing separator.
std::filesystem::path folderPath(const std::string& name);

// Writes the folder `name` as a whole: its parent must exist; leftovers of killed runs are
// cleaned (recoverFolderLeftovers); an existing folder is replaced only when `replaceable` says
// so, asked before and again at the end (files may appear meanwhile); `fill` writes into a fresh
// DIR.partial-TAG, which replaceFolder then puts in place. Any failure removes the staging folder
// and leaves the folder as it was. Messages about the folder itself start with `name`.
Status writeFolderWhole(const std::string& name,
                        const std::function<Status(const std::filesystem::path& dir)>& replaceable,
                        const std::function<Status(const std::filesystem::path& staging)>& fill);

} // namespace ndfmip
