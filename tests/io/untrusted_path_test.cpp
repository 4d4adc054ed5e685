// The untrusted-path policy and printable text (paths.h): NUL and control characters refused in
// every path the library opens or writes, bytes that are not UTF-8 escaped in messages.
#include <gtest/gtest.h>

#include <filesystem>
#include <iterator>
#include <string>

#include "ndfmip/bake_file.h"
#include "ndfmip/io.h"
#include "ndfmip/paths.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace std::string_literals;

namespace ndfmip::test {
namespace {

TEST(UntrustedPath, NulAndControlCharactersAreRefusedWithTheirPlace) {
    EXPECT_TRUE(checkUntrustedPath("maps/a b/é\xFF.png"));
    EXPECT_TRUE(checkUntrustedPath(""));
    const Status nul = checkUntrustedPath("a.png\0x"s);
    ASSERT_FALSE(nul);
    EXPECT_NE(nul.error.find("'a.png?x'"), std::string::npos) << nul.error;
    EXPECT_NE(nul.error.find("NUL character (byte 5)"), std::string::npos) << nul.error;
    for (const char c : {'\n', '\r', '\t', '\x1b', '\x7f', '\x01'}) {
        const Status s = checkUntrustedPath("x"s + c);
        ASSERT_FALSE(s) << int(c);
        char hex[8];
        std::snprintf(hex, sizeof hex, "0x%02X", unsigned(static_cast<unsigned char>(c)));
        EXPECT_NE(s.error.find(hex), std::string::npos) << s.error;
        EXPECT_EQ(s.error.find(c), std::string::npos) << "the character itself is in the message";
    }
}

TEST(UntrustedPath, EveryReaderAndWriterRefusesAPathANulWouldCutShort) {
    TempDir tmp{"untrusted_path"};
    const std::string png = tmp.file("a.png");
    Image map(4, 4, 3);
    for (float& v : map.pixels) v = 0.5f;
    ASSERT_TRUE(savePng(png, map, 8));
    // "a.png\0x" must not read a.png.
    const std::string cut = png + "\0x"s;
    Result<SourceImage> read = loadImage(cut);
    ASSERT_FALSE(read);
    EXPECT_NE(read.error().message.find("NUL"), std::string::npos) << read.error().message;
    EXPECT_FALSE(sha256File(cut));
    // "X\0/../elsewhere" must not write beside X.
    const std::string escape = tmp.file("X") + "\0/../elsewhere"s;
    EXPECT_FALSE(writeFileAtomic(escape, "bytes"));
    EXPECT_FALSE(savePng(escape, map, 8));
    Result<BakeFileReport> baked = bakeFile(png, escape, BakeFileOptions{});
    ASSERT_FALSE(baked);
    EXPECT_NE(baked.error().message.find("NUL"), std::string::npos) << baked.error().message;
    BakeFileOptions gloss;
    gloss.gloss = png + "\0"s;
    gloss.maxExponent = 10.f;
    EXPECT_FALSE(bakeFile(png, tmp.file("out"), gloss));
    EXPECT_EQ(std::distance(fs::directory_iterator(tmp.path), fs::directory_iterator()), 1)
        << "only a.png";
}

TEST(Printable, InvalidUtf8IsEscapedValidUtf8KeptControlsHidden) {
    EXPECT_EQ(printable("plain.png"), "plain.png");
    EXPECT_EQ(printable("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x99\x82"),
              "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x99\x82");
    EXPECT_EQ(printable("a\xFF"
                        "b"),
              "a\\xFFb");
    EXPECT_EQ(printable("\xC3("), "\\xC3(");                 // a lead byte without its continuation
    EXPECT_EQ(printable("\xE2\x82"), "\\xE2\\x82");          // a cut sequence
    EXPECT_EQ(printable("\xC0\xAF"), "\\xC0\\xAF");          // an overlong '/'
    EXPECT_EQ(printable("\xED\xA0\x80"), "\\xED\\xA0\\x80"); // a UTF-16 surrogate
    EXPECT_EQ(printable("a\nb\x1b[2J\x7f"), "a?b?[2J?");
    EXPECT_EQ(printable("\xC2\x9B"
                        "1m"),
              "?1m"); // C1 CSI
    // Cut by its output's length, at a whole character or escape.
    EXPECT_EQ(printable(std::string(10, '\xFF'), 9), "\\xFF\\xFF\xE2\x80\xA6");
    EXPECT_EQ(printable("\xC3\xA9\xC3\xA9", 3), "\xC3\xA9\xE2\x80\xA6");
    EXPECT_EQ(shortened("x\xFF"), "x\\xFF");
    EXPECT_EQ(quote("x\xFFy"), "'x\\xFFy'");
}

} // namespace
} // namespace ndfmip::test
