// kiln merge: sample-range and crop shards combine into exactly the single-process film, EXR and
// PNG; overlapping, missing, unfinished and foreign shards are refused.
#include "long_render_support.h"
#include "renderer/long_render.h"
#include "renderer/shard_merge.h"

namespace kiln {
namespace {

namespace fs = std::filesystem;

// Shards of one small render, written as checkpoints; ids included (first-sample channels).
struct ShardRenders : test::LoadedSpheres {
    fs::path dir = test::scratchDir();

    RenderJobOptions options(int spp) const {
        RenderJobOptions o =
            test::jobOptions(32, 24, spp, {}, AovRequest::parse("default,primid,objectid", 5));
        return o;
    }
    // Renders samples [a, b) of region [x0, x1) x [y0, y1) (x1 = 0: whole image) to a checkpoint.
    std::string shard(const std::string& name, int a, int b, int x0 = 0, int x1 = 0, int y0 = 0,
                      int y1 = 0, int maxDepth = 5) const {
        RenderJobOptions o = options(b);
        o.settings.sampleStart = a;
        o.path.maxDepth = maxDepth;
        o.settings.regionX0 = x0, o.settings.regionX1 = x1;
        o.settings.regionY0 = y0, o.settings.regionY1 = y1;
        RenderJob job(scene, *accel, o);
        LongRenderOptions lo;
        lo.checkpointPath = (dir / (name + ".ckpt")).string();
        lo.fingerprint = checkpointFingerprint(job, test::spheres(), {});
        runLongRender(job, lo);
        return lo.checkpointPath;
    }
    Film whole(int spp) const { return test::renderJob(scene, *accel, options(spp)); }
};

TEST(Merge, FourSampleRangeShardsEqualTheOneProcessFilm) {
    ShardRenders r;
    std::vector<std::string> shards{r.shard("c", 9, 20), r.shard("a", 0, 1), r.shard("d", 20, 32),
                                    r.shard("b", 1, 9)};
    MergedRender merged = mergeShards(shards);
    EXPECT_EQ(test::filmState(merged.film), test::filmState(r.whole(32)));
    EXPECT_EQ(merged.info.metadata.at("spp"), "32");
    EXPECT_EQ(merged.info.metadata.at("merged_shards"), "4");
    EXPECT_EQ(merged.info.sampleEnd, 32);
}

TEST(Merge, FourCropShardsEqualTheOneProcessFilm) {
    ShardRenders r;
    std::vector<std::string> shards{
        r.shard("q1", 0, 8, 0, 13, 0, 10), r.shard("q2", 0, 8, 13, 32, 0, 10),
        r.shard("q3", 0, 8, 0, 13, 10, 24), r.shard("q4", 0, 8, 13, 32, 10, 24)};
    MergedRender merged = mergeShards(shards);
    EXPECT_EQ(test::filmState(merged.film), test::filmState(r.whole(8)));
}

TEST(Merge, OverlapsGapsUnfinishedAndForeignShardsAreRefused) {
    ShardRenders r;
    std::string a = r.shard("a", 0, 4), b = r.shard("b", 4, 8), bb = r.shard("bb", 3, 8),
                c = r.shard("c", 5, 8), left = r.shard("left", 0, 4, 0, 16, 0, 24),
                deep = r.shard("deep", 4, 8, 0, 0, 0, 0, 6);
    auto refused = [](const std::vector<std::string>& shards, const char* why) {
        try {
            mergeShards(shards);
            ADD_FAILURE() << "merged: " << why;
        } catch (const CheckpointError& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    refused({a, bb}, "overlap");
    refused({a, c}, "samples 4..4 of pixels x 0..31, y 0..23 are in no shard");
    refused({b}, "samples 0..3");
    refused({a, b, left}, "overlap");
    refused({left, b}, "in no shard");
    refused({a, deep}, "max_depth");
    // A shard stopped before its end (as SIGTERM leaves it) is not merged.
    CheckpointInfo info;
    Film film = readCheckpoint(b, info);
    info.complete = false;
    writeCheckpoint(b, info, film);
    refused({a, b}, "unfinished");
}

// The command line end to end: 2 sample ranges x 2 crop halves, merged, equal the single render's
// EXR pixels and PNG bytes; a bad set is a one-line exit 2.
TEST(Merge, CommandLineShardsGiveTheSingleRendersExrAndPng) {
    auto dir = test::scratchDir();
    auto base = [&](const std::string& n) { return (dir / n).string(); };
    std::vector<std::string> common{"render", test::spheres(), "-r", "40", "30",
                                    "-q",     "--aov",         "all"};
    auto with = [&](std::vector<std::string> more) {
        std::vector<std::string> a = common;
        a.insert(a.end(), more.begin(), more.end());
        return a;
    };
    ASSERT_EQ(test::runKilnProcess(with({"-s", "12", "-o", base("one")})), 0);
    int n = 0;
    std::vector<std::string> merge{"merge"};
    for (const char* range : {"0 5", "5 12"})
        for (const char* crop : {"0 1 0 0.5", "0 1 0.5 1"}) {
            std::string name = base(std::string("s").append(std::to_string(n++)));
            std::vector<std::string> args = with({"-o", name});
            std::istringstream rs(range), cs(crop);
            std::string w;
            args.push_back("--sample-range");
            while (rs >> w) args.push_back(w);
            args.push_back("--crop");
            while (cs >> w) args.push_back(w);
            ASSERT_EQ(test::runKilnProcess(args), 0) << range << " " << crop;
            merge.push_back(name + ".ckpt");
        }
    merge.insert(merge.end(), {"-o", base("merged")});
    ASSERT_EQ(test::runKilnProcess(merge), 0);
    EXPECT_TRUE(test::readExrPixels(base("merged") + ".exr") ==
                test::readExrPixels(base("one") + ".exr"));
    EXPECT_EQ(test::readText(base("merged") + ".png"), test::readText(base("one") + ".png"));

    std::string err = base("err.txt");
    EXPECT_EQ(test::runKilnProcess({"merge", merge[1], merge[1], "-o", base("bad")}, -1, 0, err),
              2);
    std::string text = test::readText(err);
    EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 1) << text;
}

}  // namespace
}  // namespace kiln
