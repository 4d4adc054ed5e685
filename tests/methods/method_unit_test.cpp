// The method table: every unit describes the bake its own bake function makes, and every
// shader reads a method that exists.
#include <cmath>
#include <set>

#include <gtest/gtest.h>

#include "methods/method_unit.h"
#include "ndfmip/pyramid.h"

namespace ndfmip {
namespace {

// A bumpy 16x16 map: normals tilted by up to ~35 degrees.
SharedImage bumpyNormals() {
    auto image = std::make_shared<Image>(16, 16, 3);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            const glm::vec3 n = glm::normalize(
                glm::vec3(0.7f * std::sin(0.9f * float(x)), 0.5f * std::cos(1.3f * float(y)), 1.f));
            float* p = image->at(x, y);
            p[0] = n.x, p[1] = n.y, p[2] = n.z;
        }
    return image;
}

BakeOptions smallOptions() {
    BakeOptions o;
    o.parameters["order"] = 3;
    o.parameters["lobes"] = 2;
    return o;
}

TEST(MethodUnit, PlanesAreWhatTheBakeMakes) {
    const Pyramid pyramid = buildPyramid(bumpyNormals());
    for (const MethodUnit& unit : methodUnits()) {
        SCOPED_TRACE(unit.name);
        const Bake bake = unit.bake(pyramid, smallOptions());
        EXPECT_EQ(bake.method, unit.method);
        for (const MethodParameter& r : unit.parameters) {
            if (!r.recorded || !(r.commands & kParameterBake)) continue;
            ASSERT_TRUE(bake.parameters.count(r.key)) << r.key;
            EXPECT_EQ(bake.parameters.at(r.key), smallOptions().parameters.at(r.key)) << r.key;
            EXPECT_GE(bake.parameters.at(r.key), r.min);
            EXPECT_LE(bake.parameters.at(r.key), r.max);
        }
        const std::vector<PlaneInfo> expected =
            unit.planes(bake.parameters, findPlane(bake.planes, "color0") >= 0);
        ASSERT_EQ(bake.planes.size(), expected.size());
        for (size_t p = 0; p < expected.size(); ++p) {
            EXPECT_EQ(bake.planes[p].name, expected[p].name);
            EXPECT_EQ(bake.planes[p].channels.size(), expected[p].channels.size());
            EXPECT_EQ(bake.planes[p].linear, expected[p].linear);
            EXPECT_EQ(bake.levels.front()[p]->channels, int(expected[p].channels.size()));
        }
    }
}

// inspect --ndf histograms level-0 normals read back from any bake: each unit must return the
// map's own normal from its level-0 planes.
TEST(MethodUnit, LevelZeroNormalIsTheMapsNormal) {
    const SharedImage normals = bumpyNormals();
    const Pyramid pyramid = buildPyramid(normals);
    for (const MethodUnit& unit : methodUnits()) {
        SCOPED_TRACE(unit.name);
        const Bake bake = unit.bake(pyramid, smallOptions());
        for (int y = 0; y < 16; y += 5)
            for (int x = 0; x < 16; x += 3) {
                std::vector<float> texel;
                for (const SharedImage& plane : bake.levels.front())
                    texel.insert(texel.end(), plane->at(x, y), plane->at(x, y) + plane->channels);
                const glm::vec3 n = glm::normalize(unit.levelZeroNormal(texel.data()));
                const float* truth = normals->at(x, y);
                EXPECT_NEAR(glm::dot(n, glm::vec3(truth[0], truth[1], truth[2])), 1.f, 1e-4f)
                    << x << "," << y;
            }
    }
}

TEST(MethodUnit, ShadersReadExistingMethodsAndNamesAreUnique) {
    std::set<std::string> names;
    for (const MethodUnit& unit : methodUnits())
        EXPECT_TRUE(names.insert(unit.name).second) << unit.name;
    std::set<std::string> shaderNames;
    for (const MethodShader& shader : methodShaders()) {
        EXPECT_TRUE(shaderNames.insert(shader.name).second) << shader.name;
        EXPECT_NO_THROW(methodUnit(shader.bake));
        EXPECT_NE(renderMethodNames().find(shader.name), std::string::npos) << shader.name;
    }
    for (const MethodUnit& unit : methodUnits()) {
        EXPECT_TRUE(shaderNames.count(unit.name))
            << "every bake method renders under its own name: " << unit.name;
        EXPECT_EQ(methodFromString(unit.name), unit.method);
    }
}

} // namespace
} // namespace ndfmip
