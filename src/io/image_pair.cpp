// An EXR and its PNG preview written as one pair (saveExrWithPreview, io.h).
#include <unistd.h>

#include <filesystem>

#include "io/crash_recovery.h"
#include "ndfmip/io.h"

namespace ndfmip {

Status saveExrWithPreview(const std::string& exrPath, const Image& image,
                          const std::string& pngPath, const Image& preview) {
    // What a killed earlier run left beside either name (the temporaries below included).
    removeStaleTemporaries(exrPath);
    if (!pngPath.empty()) removeStaleTemporaries(pngPath);
    const std::string suffix = ".tmp-" + writerTag() + "-render";
    const std::string exrTemp = exrPath + suffix;
    const std::string pngTemp = pngPath.empty() ? "" : pngPath + suffix;
    auto fail = [&](std::string message, const std::string& temp, const std::string& file) {
        ::unlink(exrTemp.c_str());
        if (!pngPath.empty()) ::unlink(pngTemp.c_str());
        // Name the file asked for, not its temporary.
        if (!temp.empty() && message.rfind(temp, 0) == 0) message.replace(0, temp.size(), file);
        return Status::failure(std::move(message));
    };
    if (Status s = saveExr(exrTemp, image); !s) return fail(s.error, exrTemp, exrPath);
    if (!pngPath.empty())
        if (Status s = savePng(pngTemp, preview, 8); !s) return fail(s.error, pngTemp, pngPath);
    std::error_code ec;
    for (const std::string* file : {&pngPath, &exrPath})
        if (!file->empty() && std::filesystem::is_directory(*file, ec))
            return fail(*file + ": cannot write (a folder has that name)", "", "");
    // The preview first: the EXR, the data, is replaced last.
    if (!pngPath.empty() && (std::filesystem::rename(pngTemp, pngPath, ec), ec))
        return fail(pngPath + ": cannot write (" + ec.message() + ")", "", "");
    if (std::filesystem::rename(exrTemp, exrPath, ec), ec)
        return fail(exrPath + ": cannot write (" + ec.message() + ")", "", "");
    return Status::success();
}

} // namespace ndfmip
