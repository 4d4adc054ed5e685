// An outside program that uses the installed ndfmip package.
#include <cmath>
#include <cstdio>

#include <ndfmip/image.h>
#include <ndfmip/pyramid.h>

int main() {
    ndfmip::Image map(2, 2, 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) map.at(x, y)[2] = 1.f;
    ndfmip::Pyramid pyramid = ndfmip::buildPyramid(map);
    const float* top = ndfmip::levelMean(pyramid, int(pyramid.levels.size()) - 1).at(0, 0);
    std::printf("levels %zu, top mean z %.3f\n", pyramid.levels.size(), top[2]);
    return (pyramid.levels.size() == 2 && std::fabs(top[2] - 1.f) < 1e-6f) ? 0 : 1;
}
