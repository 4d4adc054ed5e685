// Image file reading and writing: PNG through libpng, OpenEXR through OpenEXR, the rest
// through stb_image. Nothing here throws: every failure becomes a one-line Error/Status
// that starts with the file's path.
#include "ndfmip/io.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <new>
#include <random>
#include <string_view>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openssl/evp.h>
#include <png.h>
#include <stb_image.h> // implementation lives in Debian's libstb.so

#include "io/crash_recovery.h"
#include "io/image_formats.h"
#include "io/input_file.h"
#include "ndfmip/limits.h"
#include "ndfmip/paths.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfThreading.h>
#include <half.h>
#include <thread>

namespace ndfmip {
namespace {

std::string errnoText(int err) {
    return std::strerror(err);
}

std::string stbReason() {
    const char* reason = stbi_failure_reason();
    return reason ? reason : "unknown error";
}

bool startsWith(std::string_view bytes, std::string_view magic) {
    return bytes.size() >= magic.size() && bytes.substr(0, magic.size()) == magic;
}

// ---- PNG reading (libpng's full API) ---------------------------------------------------------
// The simplified png_image API premultiplies alpha in 16-bit output and applies gAMA/sRGB
// conversions; a normal map is data, so we read the stored samples untouched instead.

struct PngReadJob {
    std::string_view bytes;
    size_t position = 0;
    uint32_t width = 0, height = 0;
    int channels = 0, bits = 0;
    std::vector<unsigned char> samples; // rows of channels * bits/8 bytes, host byte order
    char message[256] = "";
};

void pngError(png_structp png, png_const_charp message) {
    auto* job = static_cast<PngReadJob*>(png_get_error_ptr(png));
    std::snprintf(job->message, sizeof job->message, "%s", message);
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {} // e.g. "known incorrect sRGB profile": harmless

void pngReadBytes(png_structp png, png_bytep out, size_t count) {
    auto* job = static_cast<PngReadJob*>(png_get_io_ptr(png));
    if (count > job->bytes.size() - job->position) png_error(png, "file is truncated");
    std::memcpy(out, job->bytes.data() + job->position, count);
    job->position += count;
}

// Everything that outlives a longjmp lives in `job` (outside this frame) and no C++ object
// with a destructor is created between setjmp and the libpng calls, so the jump is safe.
bool decodePngSamples(PngReadJob& job) {
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &job, pngError, pngWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
        return false;
    }
    png_set_read_fn(png, &job, pngReadBytes);
    png_read_info(png, info);
    png_set_expand(png); // palette -> RGB, grey < 8 bits -> 8 bits, tRNS -> alpha
    if (png_get_bit_depth(png, info) == 16 && std::endian::native == std::endian::little)
        png_set_swap(png);
    int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    job.width = png_get_image_width(png, info);
    job.height = png_get_image_height(png, info);
    job.channels = png_get_channels(png, info);
    job.bits = png_get_bit_depth(png, info);
    size_t rowBytes = png_get_rowbytes(png, info);
    bool allocated = true;
    try {
        job.samples.resize(rowBytes * job.height);
    } catch (const std::exception&) {
        allocated = false;
    }
    if (!allocated) png_error(png, "image too large for memory");
    for (int pass = 0; pass < passes; ++pass)
        for (uint32_t y = 0; y < job.height; ++y)
            png_read_row(png, job.samples.data() + y * rowBytes, nullptr);
    png_read_end(png, nullptr); // checks the rest of the file (CRCs, IEND)
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
}

uint32_t be32(std::string_view b, size_t at) {
    uint32_t v = 0;
    for (size_t i = 0; i < 4; ++i) v = v << 8 | uint8_t(b[at + i]);
    return v;
}

// The size in the IHDR chunk (which must come first) against the input limits, and against the
// file's length: deflate expands at most 1032:1, so compressed rows shorter than a 1032nd of
// the raw ones cannot hold the image. Both before libpng allocates anything.
Status checkPngHeader(const std::string& path, std::string_view b) {
    if (b.size() < 33 || b.substr(12, 4) != "IHDR") return Status::success(); // libpng reports it
    const uint64_t width = be32(b, 16), height = be32(b, 20);
    if (Status size = checkDecodedSize(path, int64_t(width), int64_t(height)); !size) return size;
    const int bits = uint8_t(b[24]), colourType = uint8_t(b[25]);
    const int channels = colourType == 2 ? 3 : colourType == 4 ? 2 : colourType == 6 ? 4 : 1;
    const uint64_t raw = height * (1 + (width * uint64_t(channels * bits) + 7) / 8);
    if (raw > 1040 * uint64_t(b.size()) + 4096)
        return Status::failure(path + ": truncated PNG (" + std::to_string(b.size()) +
                               " bytes cannot hold " + std::to_string(width) + "x" +
                               std::to_string(height) + " pixels)");
    return Status::success();
}

Result<SourceImage> loadPng(const std::string& path, std::string_view bytes) {
    if (Status header = checkPngHeader(path, bytes); !header) return Error{header.error};
    PngReadJob job;
    job.bytes = bytes;
    if (!decodePngSamples(job))
        return fileError(path, std::string("corrupt or truncated PNG (") + job.message + ")");
    if (job.channels < 1 || job.channels > 4 || (job.bits != 8 && job.bits != 16))
        return fileError(path, "unsupported PNG sample layout");
    SourceImage out;
    out.format = "png";
    out.bitsPerChannel = job.bits;
    out.image = Image(int(job.width), int(job.height), job.channels);
    auto& pixels = out.image.pixels;
    if (job.bits == 8) {
        for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = job.samples[i] / 255.f;
    } else {
        for (size_t i = 0; i < pixels.size(); ++i) {
            uint16_t v;
            std::memcpy(&v, job.samples.data() + 2 * i, 2);
            pixels[i] = v / 65535.f;
        }
    }
    return out;
}

// ---- OpenEXR reading -------------------------------------------------------------------------

// Which channels to read: RGB(A), Y(A), RG, R, or the only channel there is.
Result<std::vector<std::string>> exrChannelsToRead(const std::string& path,
                                                   const Imf::ChannelList& list) {
    auto has = [&](const char* name) { return list.findChannel(name) != nullptr; };
    bool alpha = has("A");
    if (has("R") && has("G") && has("B"))
        return alpha ? std::vector<std::string>{"R", "G", "B", "A"}
                     : std::vector<std::string>{"R", "G", "B"};
    if (has("Y")) return alpha ? std::vector<std::string>{"Y", "A"} : std::vector<std::string>{"Y"};
    if (has("R") && has("G")) return std::vector<std::string>{"R", "G"};
    if (has("R")) return std::vector<std::string>{"R"};
    std::vector<std::string> all;
    for (auto it = list.begin(); it != list.end(); ++it) all.push_back(it.name());
    if (all.size() == 1) return all;
    std::string names;
    for (const auto& n : all) names += (names.empty() ? "" : ", ") + n;
    return fileError(path, "no R,G,B or Y channels in EXR (has: " + names + ")");
}

// OpenEXR reading from memory: the file was read (and checked to be a regular file of bounded
// size) by us, so OpenEXR never opens a path itself.
class MemoryIStream : public Imf::IStream {
  public:
    explicit MemoryIStream(std::string_view bytes) : Imf::IStream("memory"), bytes_(bytes) {}
    bool read(char c[], int n) override {
        if (n < 0 || position_ > bytes_.size() || size_t(n) > bytes_.size() - position_)
            throw Iex::InputExc("unexpected end of file");
        std::memcpy(c, bytes_.data() + position_, size_t(n));
        position_ += uint64_t(n);
        return position_ < bytes_.size();
    }
    uint64_t tellg() override { return position_; }
    void seekg(uint64_t pos) override { position_ = pos; }

  private:
    std::string_view bytes_;
    uint64_t position_ = 0;
};

Result<SourceImage> loadExrUnchecked(const std::string& path, std::string_view bytes) {
    // OpenEXR's own header check, before it sizes any table from the data window.
    const int side = int(std::min<int64_t>(inputLimits().maxSide, INT32_MAX));
    Imf::Header::setMaxImageSize(side, side);
    Imf::Header::setMaxTileSize(side, side);
    // The (first) header alone, to check the declared size before OpenEXR sizes its tables.
    MemoryIStream stream(bytes);
    char magic[8];
    stream.read(magic, 8);
    int version = 0;
    std::memcpy(&version, magic + 4, 4); // little-endian, as the file stores it
    Imf::Header first;
    first.readFrom(stream, version);
    const Imath::Box2i window = first.dataWindow();
    int64_t width = int64_t(window.max.x) - window.min.x + 1;
    int64_t height = int64_t(window.max.y) - window.min.y + 1;
    if (width <= 0 || height <= 0) return fileError(path, "image is empty (0x0)");
    if (Status size = checkDecodedSize(path, width, height); !size) return Error{size.error};
    stream.seekg(0);
    Imf::InputFile file(stream, 1);
    if (file.header().dataWindow() != window)
        return fileError(path, "inconsistent OpenEXR headers");
    // Every chunk must be there before pixels are allocated: a 10 KB file declaring a large
    // image is refused here, not after gigabytes of zeros.
    if (!file.isComplete()) return fileError(path, "truncated or incomplete OpenEXR file");
    auto names = exrChannelsToRead(path, file.header().channels());
    if (!names) return names.error();
    SourceImage out;
    out.format = "exr";
    out.isFloat = true;
    out.bitsPerChannel = 16;
    int channels = int(names->size());
    out.image = Image(int(width), int(height), channels);
    Imf::FrameBuffer frame;
    size_t xStride = sizeof(float) * channels;
    for (int c = 0; c < channels; ++c) {
        const std::string& name = names.value()[c];
        if (file.header().channels().findChannel(name)->type != Imf::HALF) out.bitsPerChannel = 32;
        frame.insert(name, Imf::Slice::Make(Imf::FLOAT, out.image.pixels.data() + c, window,
                                            xStride, xStride * size_t(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return out;
}

Result<SourceImage> loadExr(const std::string& path, std::string_view bytes) {
    try {
        return loadExrUnchecked(path, bytes);
    } catch (const std::exception& e) {
        return fileError(path, std::string("corrupt or unreadable OpenEXR file (") +
                                   shortened(e.what(), 200) + ")");
    }
}

// ---- stb_image formats -----------------------------------------------------------------------

// The formats handed to stb_image. GIF, PSD, PIC and PNM are refused: no one stores normal maps
// in them, and stb 2.27 has known flaws in some of their decoders.
std::string stbFormat(std::string_view bytes) {
    // stb takes any run of 0xFF before 0xD8 as a JPEG's start-of-image marker: so do we.
    const size_t fill = bytes.find_first_not_of('\xFF');
    if (fill > 0 && fill != std::string_view::npos && bytes[fill] == '\xD8') return "jpeg";
    if (startsWith(bytes, "BM")) return "bmp";
    if (startsWith(bytes, "GIF8")) return "gif";
    if (startsWith(bytes, "8BPS")) return "psd";
    if (startsWith(bytes, "P5") || startsWith(bytes, "P6")) return "pnm";
    if (startsWith(bytes, "\x53\x80\xF6\x34")) return "pic";
    return "tga"; // TGA has no signature; stb decides whether it is one
}

// Copies stb's interleaved samples into an Image, scaling integers to [0,1]. Divides (not
// multiplies by 1/range) so k/255 and k/65535 come out exactly as for PNG.
template <class T> Image imageFromStb(const T* data, int w, int h, int c, float range) {
    Image image(w, h, c);
    for (size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] = float(data[i]) / range;
    return image;
}

Result<SourceImage> loadWithStb(const std::string& path, std::string_view bytes) {
    SourceImage out;
    out.format = stbFormat(bytes);
    if (out.format != "jpeg" && out.format != "bmp" && out.format != "tga")
        return fileError(path, "unsupported image format (" + out.format +
                                   "; ndfmip reads PNG, JPEG, TGA, BMP, OpenEXR and Radiance HDR)");
    if (bytes.size() > size_t(INT32_MAX)) return fileError(path, "file too large for its format");
    // Truncated JPEG and BMP files are told by their structure alone; a TGA only once stb has
    // recognised it as one (TGA has no signature).
    const std::string problem = out.format == "bmp"    ? bmpProblem(bytes)
                                : out.format == "jpeg" ? jpegProblem(bytes)
                                                       : "";
    if (!problem.empty()) return fileError(path, problem);
    auto* data = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int size = int(bytes.size());
    int w = 0, h = 0, c = 0;
    if (!stbi_info_from_memory(data, size, &w, &h, &c)) {
        if (out.format == "tga") return fileError(path, "unsupported or unrecognised image format");
        return fileError(path, "corrupt " + out.format + " file (" + stbReason() + ")");
    }
    if (Status s = checkDecodedSize(path, w, h); !s) return Error{s.error};
    if (out.format == "tga" && !tgaProblem(bytes).empty())
        return fileError(path, tgaProblem(bytes));
    if (stbi_is_16_bit_from_memory(data, size)) {
        stbi_us* s = stbi_load_16_from_memory(data, size, &w, &h, &c, 0);
        if (s) out.image = imageFromStb(s, w, h, c, 65535.f);
        out.bitsPerChannel = 16;
        stbi_image_free(s);
        if (!s) return fileError(path, "corrupt image (" + stbReason() + ")");
    } else {
        stbi_uc* b = stbi_load_from_memory(data, size, &w, &h, &c, 0);
        if (b) out.image = imageFromStb(b, w, h, c, 255.f);
        stbi_image_free(b);
        if (!b) return fileError(path, "corrupt image (" + stbReason() + ")");
    }
    return out;
}

Result<SourceImage> loadRadiance(const std::string& path, std::string_view bytes) {
    Result<Image> image = decodeRadiance(bytes, path);
    if (!image) return image.error();
    SourceImage out;
    out.format = "hdr";
    out.isFloat = true;
    out.bitsPerChannel = 32;
    out.image = std::move(image.value());
    return out;
}

Result<SourceImage> decodeDetected(std::string_view bytes, const std::string& name) {
    if (bytes.empty()) return fileError(name, "file is empty");
    if (startsWith(bytes, "\x76\x2F\x31\x01")) return loadExr(name, bytes);
    if (startsWith(bytes, "\x89PNG\r\n\x1A\n")) return loadPng(name, bytes);
    if (startsWith(bytes, "#?RADIANCE") || startsWith(bytes, "#?RGBE"))
        return loadRadiance(name, bytes);
    return loadWithStb(name, bytes);
}

// ---- writing ---------------------------------------------------------------------------------

std::string tempPathFor(const std::string& path) {
    std::random_device random;
    char suffix[64];
    std::snprintf(suffix, sizeof suffix, "-%08x%08x", random(), random());
    return path + ".tmp-" + writerTag() + suffix;
}

// Writes all of `bytes` to a new file and syncs it; returns 0 or an errno value.
int writeNewFile(const std::string& path, const std::string& bytes) {
    int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) return errno;
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int err = n < 0 ? errno : EIO;
            ::close(fd);
            return err;
        }
        done += size_t(n);
    }
    // Flush to disk before the rename so a crash cannot leave an empty file under `path`.
    if (::fsync(fd) != 0) {
        int err = errno;
        ::close(fd);
        return err;
    }
    return ::close(fd) == 0 ? 0 : errno;
}

Status cannotWrite(const std::string& path, const std::string& why) {
    return Status::failure(path + ": cannot write (" + oneLine(why) + ")");
}

// An in-memory OpenEXR output stream (OpenEXR seeks back to fill in the offset table).
class MemoryOStream : public Imf::OStream {
  public:
    explicit MemoryOStream(std::string& bytes) : Imf::OStream("memory"), bytes_(bytes) {}
    void write(const char c[], int n) override {
        if (position_ + size_t(n) > bytes_.size()) bytes_.resize(position_ + size_t(n));
        std::memcpy(bytes_.data() + position_, c, size_t(n));
        position_ += size_t(n);
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t pos) override { position_ = pos; }

  private:
    std::string& bytes_;
    uint64_t position_ = 0;
};

bool validImage(const Image& image) {
    return !image.empty() && image.pixels.size() == image.texelCount() * size_t(image.channels);
}

std::vector<std::string> exrChannelNames(const Image& image,
                                         const std::vector<std::string>& given) {
    if (!given.empty()) return given;
    if (image.channels == 1) return {"Y"};
    std::vector<std::string> names{"R", "G", "B", "A"};
    names.resize(size_t(image.channels));
    return names;
}

Status checkExrNames(const std::string& path, const Image& image,
                     const std::vector<std::string>& names) {
    if (names.size() != size_t(image.channels))
        return cannotWrite(path, std::to_string(names.size()) + " channel names for " +
                                     std::to_string(image.channels) + " channels");
    for (size_t i = 0; i < names.size(); ++i) {
        if (names[i].empty()) return cannotWrite(path, "empty channel name");
        if (std::find(names.begin(), names.begin() + long(i), names[i]) != names.begin() + long(i))
            return cannotWrite(path, "channel name " + names[i] + " given twice");
    }
    return Status::success();
}

void encodeExr(const Image& image, const std::vector<std::string>& names, bool half,
               std::string& bytes) {
    // ZIP-compressing float data dominates a bake's time: let OpenEXR use every core.
    static const bool threaded = [] {
        Imf::setGlobalThreadCount(int(std::max(1u, std::thread::hardware_concurrency())));
        return true;
    }();
    (void)threaded;
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    header.zipCompressionLevel() = 1; // float noise barely compresses harder; level 1 is ~3x faster
    Imf::FrameBuffer frame;
    // Half pixels are converted up front; OpenEXR reads either layout through its slices.
    std::vector<Imath::half> halves;
    if (half) halves.assign(image.pixels.begin(), image.pixels.end());
    const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
    const size_t valueSize = half ? sizeof(Imath::half) : sizeof(float);
    const size_t xStride = valueSize * size_t(image.channels);
    char* base = half ? reinterpret_cast<char*>(halves.data())
                      : reinterpret_cast<char*>(const_cast<float*>(image.pixels.data()));
    for (int c = 0; c < image.channels; ++c) {
        header.channels().insert(names[size_t(c)], Imf::Channel(type));
        frame.insert(names[size_t(c)], Imf::Slice(type, base + c * valueSize, xStride,
                                                  xStride * size_t(image.width)));
    }
    MemoryOStream stream(bytes);
    Imf::OutputFile file(stream, header); // its destructor writes the offset table
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
}

// ---- PNG writing (libpng's full API, no colour-space chunks) ---------------------------------

struct PngWriteJob {
    const Image* image = nullptr;
    int bits = 8;
    std::vector<unsigned char> samples; // big-endian rows, as PNG stores them
    std::string* out = nullptr;
    char message[256] = "";
};

void pngWriteBytes(png_structp png, png_bytep data, size_t count) {
    auto* job = static_cast<PngWriteJob*>(png_get_io_ptr(png));
    bool ok = true;
    try {
        job->out->append(reinterpret_cast<const char*>(data), count);
    } catch (const std::exception&) {
        ok = false;
    }
    if (!ok) png_error(png, "out of memory");
}

void pngFlush(png_structp) {}

void pngWriteError(png_structp png, png_const_charp message) {
    auto* job = static_cast<PngWriteJob*>(png_get_error_ptr(png));
    std::snprintf(job->message, sizeof job->message, "%s", message);
    png_longjmp(png, 1);
}

// Quantises to 8 or 16 bits, clamping to [0,1] (NaN -> 0) and rounding to nearest.
void quantisePng(PngWriteJob& job) {
    const auto& pixels = job.image->pixels;
    int bytesPer = job.bits / 8;
    float top = job.bits == 8 ? 255.f : 65535.f;
    job.samples.resize(pixels.size() * size_t(bytesPer));
    for (size_t i = 0; i < pixels.size(); ++i) {
        float v = pixels[i] > 0.f ? std::min(pixels[i], 1.f) : 0.f;
        auto q = uint32_t(std::lround(v * top));
        if (bytesPer == 1) {
            job.samples[i] = static_cast<unsigned char>(q);
        } else {
            job.samples[2 * i] = static_cast<unsigned char>(q >> 8);
            job.samples[2 * i + 1] = static_cast<unsigned char>(q & 0xFF);
        }
    }
}

// Same longjmp rules as decodePngSamples.
bool writePngStream(PngWriteJob& job) {
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &job, pngWriteError, pngWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, info ? &info : nullptr);
        return false;
    }
    static const int colourTypes[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                      PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
    const Image& image = *job.image;
    png_set_write_fn(png, &job, pngWriteBytes, pngFlush);
    png_set_IHDR(png, info, png_uint_32(image.width), png_uint_32(image.height), job.bits,
                 colourTypes[image.channels - 1], PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 3); // level 6 (default) is 2-3x slower for ~5% smaller files
    png_write_info(png, info);
    size_t rowBytes = size_t(image.width) * size_t(image.channels) * size_t(job.bits / 8);
    for (int y = 0; y < image.height; ++y)
        png_write_row(png, job.samples.data() + size_t(y) * rowBytes);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

} // namespace

Result<SourceImage> decodeImage(std::string_view bytes, const std::string& name) {
    try {
        auto loaded = decodeDetected(bytes, name);
        if (loaded && loaded->image.empty()) return fileError(name, "image is empty (0x0)");
        return loaded;
    } catch (const std::bad_alloc&) {
        return Error{outOfMemoryMessage(name)};
    } catch (const std::exception& e) {
        return fileError(name, std::string("cannot read (") + shortened(e.what(), 200) + ")");
    }
}

Result<SourceImage> loadImage(const std::string& path) {
    Result<std::string> bytes = readRegularFile(path, inputLimits().maxImageFileBytes);
    if (!bytes) return bytes.error();
    return decodeImage(bytes.value(), path);
}

Status saveExr(const std::string& path, const Image& image,
               const std::vector<std::string>& channelNames, bool half) {
    if (!validImage(image)) return cannotWrite(path, "empty or inconsistent image");
    std::vector<std::string> names = exrChannelNames(image, channelNames);
    if (Status status = checkExrNames(path, image, names); !status) return status;
    std::string bytes;
    try {
        encodeExr(image, names, half, bytes);
    } catch (const std::exception& e) {
        return cannotWrite(path, e.what());
    }
    return writeFileAtomic(path, bytes);
}

Result<std::string> encodePng(const Image& image, int bitsPerChannel) {
    if (!validImage(image)) return Error{"cannot encode an empty or inconsistent image as PNG"};
    if (image.channels > 4)
        return Error{"PNG holds 1 to 4 channels, not " + std::to_string(image.channels)};
    if (bitsPerChannel != 8 && bitsPerChannel != 16)
        return Error{"PNG bit depth must be 8 or 16, not " + std::to_string(bitsPerChannel)};
    std::string bytes;
    PngWriteJob job;
    job.image = &image;
    job.bits = bitsPerChannel;
    job.out = &bytes;
    try {
        quantisePng(job);
    } catch (const std::exception& e) {
        return Error{std::string("PNG encoder: ") + oneLine(e.what())};
    }
    if (!writePngStream(job)) return Error{std::string("PNG encoder: ") + oneLine(job.message)};
    return bytes;
}

Status savePng(const std::string& path, const Image& image, int bitsPerChannel) {
    auto bytes = encodePng(image, bitsPerChannel);
    if (!bytes) return cannotWrite(path, bytes.error().message);
    return writeFileAtomic(path, bytes.value());
}

Status writeFileAtomic(const std::string& path, const std::string& bytes) {
    if (Status s = checkUntrustedPath(path); !s) return s;
    removeStaleTemporaries(path); // what a killed earlier run left beside the same file
    std::string temp = tempPathFor(path);
    if (int err = writeNewFile(temp, bytes); err != 0) {
        ::unlink(temp.c_str()); // fails harmlessly when it was never created
        return cannotWrite(path, errnoText(err));
    }
    std::error_code ec;
    std::filesystem::rename(temp, path, ec);
    if (ec) {
        ::unlink(temp.c_str());
        return cannotWrite(path, ec.message());
    }
    return Status::success();
}

namespace {

std::string hexDigest(const unsigned char* digest, unsigned int length) {
    static const char hex[] = "0123456789abcdef";
    std::string text;
    for (unsigned int i = 0; i < length; ++i) {
        text += hex[digest[i] >> 4];
        text += hex[digest[i] & 15];
    }
    return text;
}

} // namespace

Result<std::string> sha256File(const std::string& path) {
    Result<int> fd = openRegularFile(path);
    if (!fd) return fd.error();
    std::FILE* file = ::fdopen(fd.value(), "rb");
    if (!file) {
        ::close(fd.value());
        return fileError(path, "cannot read: " + errnoText(errno));
    }
    EVP_MD_CTX* ctx = EVP_MD_CTX_new();
    bool ok = ctx && EVP_DigestInit_ex(ctx, EVP_sha256(), nullptr) == 1;
    std::array<unsigned char, 1 << 16> chunk;
    size_t got;
    while (ok && (got = std::fread(chunk.data(), 1, chunk.size(), file)) > 0)
        ok = EVP_DigestUpdate(ctx, chunk.data(), got) == 1;
    bool readError = std::ferror(file) != 0;
    std::fclose(file);
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    ok = ok && !readError && EVP_DigestFinal_ex(ctx, digest, &length) == 1;
    EVP_MD_CTX_free(ctx);
    if (!ok) return fileError(path, readError ? "read error" : "SHA-256 failed");
    return hexDigest(digest, length);
}

std::string sha256Text(const std::string& bytes) {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr);
    return hexDigest(digest, length);
}

} // namespace ndfmip
