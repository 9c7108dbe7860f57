// Helpers of the batch and farm tests: the kiln binary as a child process and image comparison.
#pragma once

#include <OpenImageIO/imagebuf.h>

#include <nlohmann/json.hpp>

#include "renderer/farm/child_process.h"
#include "test_support.h"

namespace kiln::test {

inline farm::CommandResult kiln(const std::vector<std::string>& args) {
    return farm::runCapturing(KILN_BINARY, args);
}

// A job file of one scene's turntable of `frames` frames (camera "orbit") with `args`.
inline std::string writeTurntableJob(const std::filesystem::path& file, const std::string& output,
                                     const std::string& scene, const nlohmann::json& args,
                                     int frames) {
    nlohmann::json camera = {{"name", "orbit"}, {"turntable", frames}};
    nlohmann::json job = {{"output", output},
                          {"scenes", nlohmann::json::array({scene})},
                          {"args", args},
                          {"cameras", nlohmann::json::array({camera})}};
    return writeFile(file, job.dump());
}

// Every channel of every pixel of two EXRs, compared as bits: "" when equal, else what differs.
inline std::string exrDifference(const std::string& a, const std::string& b) {
    OIIO::ImageBuf x(a), y(b);
    if (!x.read(0, 0, true, OIIO::TypeDesc::FLOAT) || !y.read(0, 0, true, OIIO::TypeDesc::FLOAT))
        return "cannot read " + a + " or " + b;
    const OIIO::ImageSpec &sx = x.spec(), &sy = y.spec();
    if (sx.width != sy.width || sx.height != sy.height || sx.nchannels != sy.nchannels ||
        sx.channelnames != sy.channelnames)
        return "layouts differ";
    std::vector<float> px(size_t(sx.image_pixels()) * size_t(sx.nchannels)), py(px.size());
    x.get_pixels(x.roi(), OIIO::TypeDesc::FLOAT, px.data());
    y.get_pixels(y.roi(), OIIO::TypeDesc::FLOAT, py.data());
    for (size_t i = 0; i < px.size(); ++i)
        if (std::memcmp(&px[i], &py[i], sizeof(float)) != 0)
            return "value " + std::to_string(i) + " (channel " +
                   sx.channelnames[i % size_t(sx.nchannels)] + "): " + std::to_string(px[i]) +
                   " != " + std::to_string(py[i]);
    return "";
}

}  // namespace kiln::test
