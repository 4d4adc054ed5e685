// What a killed run leaves behind, and how the next run cleans it up. Writers name their
// temporary siblings after their process: a folder DIR is staged as DIR.partial-PID and, where
// the file system cannot exchange two folders atomically, set aside as DIR.old-PID while the new
// one moves in; a file PATH is written as PATH.tmp-PID-RANDOM and renamed over PATH.
#pragma once

#include <cstdint>
#include <filesystem>

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

} // namespace ndfmip
