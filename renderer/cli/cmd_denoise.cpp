// kiln denoise IN.exr -o OUT.exr: the NFOR denoiser (docs/denoise.md) over an EXR that carries
// the half-buffers (kiln render --denoise, kiln merge of such shards, farm results).
#include <cstdio>
#include <filesystem>

#include "renderer/cli/cli_args.h"
#include "renderer/cli/commands.h"
#include "renderer/cli/output_check.h"
#include "renderer/cli/render_options.h"
#include "renderer/core/log.h"
#include "renderer/denoise_film.h"

namespace kiln {

int runDenoise(const std::vector<std::string>& args) {
    std::string output;
    denoise::Options options;
    ArgParser parser("denoise", "IN.exr -o OUT.exr");
    parser.option("output", "o", 1, "OUT.exr", "the denoised EXR",
                  [&output](const std::vector<std::string>& v) { output = v[0]; });
    parser.intOption("threads", "t", "worker threads (default: all cores)", options.threads, 1,
                     4096);
    parser.intOption("window", "", "the regression window's radius R: (2R+1)^2 pixels (default 4)",
                     options.windowRadius, 1, 16);
    uint32_t denoisedLight = 0;
    parser.option("denoise-aovs", "", 1, "LIST",
                  std::string("denoise these light-path AOVs too, from their half-buffers "
                              "(kiln render --denoise-aovs), comma-separated: ") +
                      AovRequest::lightNames(),
                  [&denoisedLight](const std::vector<std::string>& v) {
                      denoisedLight = parseDenoisedAovs(v[0]);
                  });
    std::vector<std::string> inputs = parser.parse(args);
    if (parser.helpRequested()) {
        std::fputs(parser.helpText().c_str(), stdout);
        std::fputs(
            "\nIN.exr must carry the half-buffers (halfA.*, halfB.*) that kiln render --denoise "
            "writes. OUT.exr is IN.exr with R,G,B denoised and the noisy beauty as noisy.R/G/B; "
            "with --denoise-aovs each named layer likewise (LAYER.R/G/B denoised, "
            "noisy.LAYER.R/G/B the raw one), from its halfA.LAYER.*, halfB.LAYER.*. "
            "Exit status: 0 done, 1 the write failed, 2 bad input.\n",
            stdout);
        return 0;
    }
    if (inputs.size() != 1) throw UsageError("needs one IN.exr");
    if (output.empty()) throw UsageError("needs -o OUT.exr");
    checkOutputBase(output);
    checkOutputFiles({output});
    double seconds = 0;
    try {
        seconds = denoiseExr(inputs[0], output, options, denoisedLight);
    } catch (const DenoiseInputError& e) {
        throw UsageError(e.what());
    } catch (const ImageReadError& e) {
        throw UsageError(e.what());
    }
    logInfo("denoised {} -> {} in {:.2f}s", inputs[0], output, seconds);
    return 0;
}

}  // namespace kiln
