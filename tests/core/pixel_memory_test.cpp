// Pixel storage: huge pages are offered only when the kernel has that many free.
#include <cstdint>

#include <gtest/gtest.h>

#include "ndfmip/image.h"

namespace ndfmip {
namespace {

TEST(PixelMemory, FreeHugePageBytesCountsOrdersNineAndUp) {
    // Orders 0..10 per zone; order k holds 2^k pages of 4 KiB, so order 9 is 2 MiB and order 10 is
    // 4 MiB.
    const char* text = "Node 0, zone      DMA      0      0      0      0      0      0      0     "
                       " 0      1      1      3 \n"
                       "Node 0, zone    DMA32      4      1      2      2      2      2      1     "
                       " 4      4      2    752 \n"
                       "Node 0, zone   Normal  14712  19432  14333   9116   5409   3550   1979    "
                       "929    468    234    242 \n";
    const size_t mib = size_t(1) << 20;
    EXPECT_EQ(freeHugePageBytes(text), (1 + 2 + 234) * 2 * mib + (3 + 752 + 242) * 4 * mib);
    EXPECT_EQ(freeHugePageBytes(""), 0u);
    EXPECT_EQ(freeHugePageBytes("Node 0, zone Normal 5 5 5\n"), 0u); // only small blocks free
    EXPECT_EQ(freeHugePageBytes("garbage without zones\n"), 0u);
}

TEST(PixelMemory, LargeAndSmallBlocksAreUsable) {
    for (size_t bytes : {size_t(0), size_t(64), size_t(5) << 20}) {
        void* p = allocatePixels(bytes);
        ASSERT_NE(p, nullptr);
        if (bytes >= (size_t(4) << 20)) {
            EXPECT_EQ(reinterpret_cast<uintptr_t>(p) % (size_t(2) << 20), 0u);
        }
        static_cast<unsigned char*>(p)[bytes ? bytes - 1 : 0] = 1;
        freePixels(p);
    }
}

} // namespace
} // namespace ndfmip
