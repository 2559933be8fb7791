// The render graph's planner, inspected without a GPU: order, culling, barrier derivation,
// layout transitions, loops and transient reuse and aliasing.
#include "gimg/engine/error.h"
#include "gimg/engine/graph.h"

#include <gtest/gtest.h>

#include <algorithm>

using namespace gimg;

namespace {

constexpr VkPipelineStageFlags2 kCompute = VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT;
constexpr VkPipelineStageFlags2 kTransfer = VK_PIPELINE_STAGE_2_ALL_TRANSFER_BIT;
constexpr VkAccessFlags2 kStorageRead = VK_ACCESS_2_SHADER_STORAGE_READ_BIT;
constexpr VkAccessFlags2 kStorageWrite = VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT;

std::vector<BarrierInfo> barriers_on(const std::vector<BarrierInfo>& all, const std::string& resource) {
    std::vector<BarrierInfo> out;
    std::copy_if(all.begin(), all.end(), std::back_inserter(out),
                 [&](const BarrierInfo& b) { return b.resource == resource; });
    return out;
}

void no_op(Cmd&) {}

}  // namespace

TEST(PlanBarriers, ReadAfterWriteWaitsForTheWriteAndMakesItVisible) {
    Graph g;
    Buffer out = Buffer::unbacked({1024, "out"});
    auto t = g.create_buffer({1024, "t"});
    auto o = g.import_buffer(out);
    g.add_compute_pass(
        "write", [&](PassBuilder& b) { t = b.write(t, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "read",
        [&](PassBuilder& b) {
            b.read(t, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    Plan plan = g.compile();

    ASSERT_EQ(plan.passes().size(), 2u);
    EXPECT_EQ(plan.passes()[0].name, "write");
    EXPECT_TRUE(plan.pass("write").barriers.empty()) << plan.describe();
    auto b = barriers_on(plan.pass("read").barriers, "t");
    ASSERT_EQ(b.size(), 1u) << plan.describe();
    EXPECT_EQ(b[0].src_stages, kCompute);
    EXPECT_EQ(b[0].src_access, kStorageWrite);
    EXPECT_EQ(b[0].dst_stages, kCompute);
    EXPECT_EQ(b[0].dst_access, kStorageRead);
    // "out" was never used before: nothing to wait for.
    EXPECT_TRUE(barriers_on(plan.pass("read").barriers, "out").empty());
}

TEST(PlanBarriers, SecondReaderInTheSameStageNeedsNoBarrier) {
    Graph g;
    Buffer out = Buffer::unbacked({16, "out"});
    auto t = g.create_buffer({1024, "t"});
    auto o = g.import_buffer(out);
    g.add_compute_pass(
        "write", [&](PassBuilder& b) { t = b.write(t, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "read1",
        [&](PassBuilder& b) {
            b.read(t, Access::ComputeRead);
            o = b.write(o, Access::ComputeReadWrite);
        },
        no_op);
    g.add_compute_pass(
        "read2",
        [&](PassBuilder& b) {
            b.read(t, Access::ComputeRead);
            o = b.write(o, Access::ComputeReadWrite);
        },
        no_op);
    Plan plan = g.compile();
    EXPECT_EQ(barriers_on(plan.pass("read1").barriers, "t").size(), 1u);
    EXPECT_TRUE(barriers_on(plan.pass("read2").barriers, "t").empty()) << plan.describe();
    // ...but "out" is written twice: write-after-write.
    auto waw = barriers_on(plan.pass("read2").barriers, "out");
    ASSERT_EQ(waw.size(), 1u);
    EXPECT_EQ(waw[0].src_access, kStorageWrite);
}

TEST(PlanBarriers, WriteAfterReadIsAnExecutionDependencyOnly) {
    Graph g;
    Buffer x = Buffer::unbacked({256, "x"});
    auto h = g.import_buffer(x);
    Buffer sink = Buffer::unbacked({256, "sink"});
    auto s = g.import_buffer(sink);
    g.add_compute_pass(
        "read",
        [&](PassBuilder& b) {
            b.read(h, Access::ComputeRead);
            s = b.write(s, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "overwrite", [&](PassBuilder& b) { h = b.write(h, Access::TransferDst); }, no_op);
    Plan plan = g.compile();
    EXPECT_TRUE(barriers_on(plan.pass("read").barriers, "x").empty());
    auto war = barriers_on(plan.pass("overwrite").barriers, "x");
    ASSERT_EQ(war.size(), 1u) << plan.describe();
    EXPECT_EQ(war[0].src_stages, kCompute);
    EXPECT_EQ(war[0].src_access, 0u);  // reads have nothing to make available
    EXPECT_EQ(war[0].dst_stages, kTransfer);
    EXPECT_EQ(war[0].dst_access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

TEST(PlanBarriers, WriteAfterWriteMakesTheFirstWriteAvailable) {
    Graph g;
    Buffer x = Buffer::unbacked({256, "x"});
    auto h = g.import_buffer(x);
    g.add_compute_pass(
        "first", [&](PassBuilder& b) { h = b.write(h, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "second", [&](PassBuilder& b) { h = b.write(h, Access::TransferDst); }, no_op);
    Plan plan = g.compile();
    auto waw = barriers_on(plan.pass("second").barriers, "x");
    ASSERT_EQ(waw.size(), 1u);
    EXPECT_EQ(waw[0].src_stages, kCompute);
    EXPECT_EQ(waw[0].src_access, kStorageWrite);
    EXPECT_EQ(waw[0].dst_access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
}

TEST(PlanBarriers, ImportsStartFromTheirLastAccessAndExportsEndAtTheNext) {
    Graph g;
    Buffer x = Buffer::unbacked({256, "x"}, Access::TransferDst);  // e.g. just uploaded
    auto h = g.import_buffer(x);
    g.add_compute_pass(
        "square", [&](PassBuilder& b) { h = b.write(h, Access::ComputeReadWrite); }, no_op);
    g.export_buffer(h, Access::HostRead);
    Plan plan = g.compile();
    auto in = barriers_on(plan.pass("square").barriers, "x");
    ASSERT_EQ(in.size(), 1u);
    EXPECT_EQ(in[0].src_stages, kTransfer);
    EXPECT_EQ(in[0].src_access, VK_ACCESS_2_TRANSFER_WRITE_BIT);
    auto out = barriers_on(plan.final_barriers(), "x");
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].src_access, kStorageWrite);
    EXPECT_EQ(out[0].dst_stages, VK_PIPELINE_STAGE_2_HOST_BIT);
    EXPECT_EQ(out[0].dst_access, VK_ACCESS_2_HOST_READ_BIT);
}

TEST(PlanBarriers, AnObjectImportedTwiceIsOneResource) {
    // Two capabilities importing the same image (filters shared by two calls) must not see two
    // resources: the second import would start from the first's initial layout again.
    Graph g;
    Image table = Image::unbacked({64, 1, Format::R32U, "table"}, Access::TransferDst);
    Buffer out = Buffer::unbacked({64, "out"});
    auto first = g.import_image(table);
    auto o = g.import_buffer(out);
    g.add_compute_pass(
        "first reader",
        [&](PassBuilder& b) {
            b.read(first, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    const auto second = g.import_image(table);
    EXPECT_EQ(second.id, first.id);
    EXPECT_EQ(second.version, first.version);
    EXPECT_EQ(g.import_buffer(out).version, o.version);  // the newest version of a written import
    g.add_compute_pass(
        "second reader",
        [&](PassBuilder& b) {
            b.read(second, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    g.export_buffer(o, Access::TransferSrc);
    Plan plan = g.compile();
    EXPECT_EQ(barriers_on(plan.pass("first reader").barriers, "table").size(), 1u) << plan.describe();
    EXPECT_TRUE(barriers_on(plan.pass("second reader").barriers, "table").empty()) << plan.describe();
}

TEST(PlanResources, ImageDescIsTheTransientsAsCreatedAndTheImportsAsItIs) {
    Graph g;
    Image table = Image::unbacked({16, 4, Format::RGBA32U, "table"});
    const auto imported = g.import_image(table);
    const auto transient = g.create_image({64, 32, Format::R32F, "img"});
    EXPECT_EQ(g.image_desc(transient).width, 64u);
    EXPECT_EQ(g.image_desc(transient).height, 32u);
    EXPECT_EQ(g.image_desc(transient).format, Format::R32F);
    EXPECT_EQ(g.image_desc(imported).width, 16u);
    EXPECT_EQ(g.image_desc(imported).format, Format::RGBA32U);
    EXPECT_THROW(g.image_desc(ImageHandle{7, 0}), Error);
}

TEST(PlanLayouts, StorageSampledTransferTransitions) {
    Graph g;
    auto img = g.create_image({64, 32, Format::R32F, "img"});
    Buffer sink = Buffer::unbacked({16, "sink"});
    auto s = g.import_buffer(sink);
    g.add_compute_pass(
        "write", [&](PassBuilder& b) { img = b.write(img, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "sample",
        [&](PassBuilder& b) {
            b.read(img, Access::ComputeSampled);
            s = b.write(s, Access::ComputeWrite);
        },
        no_op);
    g.export_image(img, Access::TransferSrc);
    Plan plan = g.compile();

    auto first = barriers_on(plan.pass("write").barriers, "img");
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].old_layout, VK_IMAGE_LAYOUT_UNDEFINED);  // a transient's contents start undefined
    EXPECT_EQ(first[0].new_layout, VK_IMAGE_LAYOUT_GENERAL);
    auto sample = barriers_on(plan.pass("sample").barriers, "img");
    ASSERT_EQ(sample.size(), 1u);
    EXPECT_EQ(sample[0].old_layout, VK_IMAGE_LAYOUT_GENERAL);
    EXPECT_EQ(sample[0].new_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(sample[0].src_access, kStorageWrite);
    EXPECT_EQ(sample[0].dst_access, VK_ACCESS_2_SHADER_SAMPLED_READ_BIT);
    auto exported = barriers_on(plan.final_barriers(), "img");
    ASSERT_EQ(exported.size(), 1u);
    EXPECT_EQ(exported[0].old_layout, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(exported[0].new_layout, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
}

TEST(PlanLayouts, ClearedAttachmentDiscardsAndLoadedAttachmentKeeps) {
    Graph g;
    Image target = Image::unbacked({32, 32, Format::RGBA8, "target"}, Access::TransferSrc);
    auto t = g.import_image(target);
    auto depth = g.create_image({32, 32, Format::D32F, "depth"});
    g.add_raster_pass(
        "clear",
        [&](PassBuilder& b) {
            t = b.color(t, ClearValue::color(0, 0, 0, 1));
            depth = b.depth(depth, ClearValue::depth(1.0f));
        },
        no_op);
    g.add_raster_pass(
        "overlay", [&](PassBuilder& b) { t = b.color(t); }, no_op);
    Plan plan = g.compile();
    auto cleared = barriers_on(plan.pass("clear").barriers, "target");
    ASSERT_EQ(cleared.size(), 1u);
    EXPECT_EQ(cleared[0].old_layout, VK_IMAGE_LAYOUT_UNDEFINED);
    EXPECT_EQ(cleared[0].new_layout, VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(cleared[0].src_stages, kTransfer);  // still waits for the earlier transfer read
    auto loaded = barriers_on(plan.pass("overlay").barriers, "target");
    ASSERT_EQ(loaded.size(), 1u);  // colour write after colour write
    EXPECT_EQ(loaded[0].old_layout, VK_IMAGE_LAYOUT_ATTACHMENT_OPTIMAL);
    EXPECT_EQ(loaded[0].src_access, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
    EXPECT_EQ(plan.culled_passes().size(), 0u);
}

TEST(PlanCulling, PassesWhoseOutputsNobodyReadsAreCulled) {
    Graph g;
    Buffer out = Buffer::unbacked({64, "out"});
    auto o = g.import_buffer(out);
    auto t1 = g.create_buffer({64, "t1"});
    auto t2 = g.create_buffer({64, "t2"});
    auto t3 = g.create_buffer({64, "t3"});
    g.add_compute_pass(
        "feeds dead", [&](PassBuilder& b) { t1 = b.write(t1, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "dead",
        [&](PassBuilder& b) {
            b.read(t1, Access::ComputeRead);
            t2 = b.write(t2, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "feeds live", [&](PassBuilder& b) { t3 = b.write(t3, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "live",
        [&](PassBuilder& b) {
            b.read(t3, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "kept", [&](PassBuilder& b) { b.keep(); }, no_op);
    Plan plan = g.compile();
    std::vector<std::string> live;
    for (const auto& p : plan.passes()) live.push_back(p.name);
    EXPECT_EQ(live, (std::vector<std::string>{"feeds live", "live", "kept"}));
    EXPECT_EQ(plan.culled_passes(), (std::vector<std::string>{"feeds dead", "dead"}));
    EXPECT_FALSE(plan.physical_resource(t1).has_value());  // only culled passes used it
}

TEST(PlanCulling, ALoopRunsWholeWhenAnyOfItsPassesIsNeeded) {
    Graph g;
    Buffer out = Buffer::unbacked({64, "out"});
    auto o = g.import_buffer(out);
    auto a = g.create_buffer({64, "a"});
    auto b = g.create_buffer({64, "b"});
    g.add_compute_pass(
        "init", [&](PassBuilder& p) { a = p.write(a, Access::ComputeWrite); }, no_op);
    g.add_loop(10, [&] {
        g.add_compute_pass(
            "a to b",
            [&](PassBuilder& p) {
                b = p.write(b, Access::ComputeReadWrite);
                a = p.write(a, Access::ComputeReadWrite);
            },
            no_op);
        g.add_compute_pass(
            "b to a",
            [&](PassBuilder& p) {
                b = p.write(b, Access::ComputeReadWrite);
                a = p.write(a, Access::ComputeReadWrite);
            },
            no_op);
    });
    g.add_compute_pass(
        "result",
        [&](PassBuilder& p) {
            p.read(a, Access::ComputeRead);
            o = p.write(o, Access::ComputeWrite);
        },
        no_op);
    Plan plan = g.compile();
    ASSERT_EQ(plan.passes().size(), 4u) << plan.describe();
    EXPECT_EQ(plan.pass("a to b").iterations, 10u);
    // Later iterations wait for the previous iteration's last pass.
    auto repeat = barriers_on(plan.pass("a to b").repeat_barriers, "a");
    ASSERT_EQ(repeat.size(), 1u);
    EXPECT_EQ(repeat[0].src_access, kStorageWrite);
    EXPECT_EQ(repeat[0].dst_access, kStorageRead | kStorageWrite);
    // The loop keeps a and b alive throughout, so they cannot share memory.
    EXPECT_NE(*plan.physical_resource(a), *plan.physical_resource(b));
}

TEST(PlanTransients, EqualDescriptionsWithDisjointLifetimesShareOnePhysicalResource) {
    Graph g;
    Buffer out = Buffer::unbacked({4096, "out"});
    auto o = g.import_buffer(out);
    auto t1 = g.create_buffer({4096, "t1"});
    auto t2 = g.create_buffer({4096, "t2"});
    auto big = g.create_buffer({8192, "big"});
    g.add_compute_pass(
        "make t1", [&](PassBuilder& b) { t1 = b.write(t1, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "use t1",
        [&](PassBuilder& b) {
            b.read(t1, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "make t2", [&](PassBuilder& b) { t2 = b.write(t2, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "make big",
        [&](PassBuilder& b) {
            b.read(t2, Access::ComputeRead);
            big = b.write(big, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "use big",
        [&](PassBuilder& b) {
            b.read(big, Access::ComputeRead);
            o = b.write(o, Access::ComputeWrite);
        },
        no_op);
    Plan plan = g.compile();
    ASSERT_TRUE(plan.physical_resource(t1) && plan.physical_resource(t2) && plan.physical_resource(big));
    EXPECT_EQ(*plan.physical_resource(t1), *plan.physical_resource(t2)) << plan.describe();
    EXPECT_NE(*plan.physical_resource(t2), *plan.physical_resource(big));
    EXPECT_EQ(plan.physical_resource_count(), 2u);
    // Reusing t1's resource for t2: the first write to t2 waits for the last read of t1.
    auto reuse = barriers_on(plan.pass("make t2").barriers, "t1|t2");
    ASSERT_EQ(reuse.size(), 1u) << plan.describe();
    EXPECT_EQ(reuse[0].src_stages, kCompute);
    EXPECT_EQ(reuse[0].dst_access, kStorageWrite);
}

TEST(PlanTransients, DisjointLifetimesAliasMemoryAndOverlappingOnesDoNot) {
    Graph g;
    Buffer out = Buffer::unbacked({64, "out"});
    auto o = g.import_buffer(out);
    auto a = g.create_buffer({1 << 20, "a"});
    auto b = g.create_buffer({1 << 16, "b"});
    auto c = g.create_buffer({1 << 18, "c"});
    g.add_compute_pass(
        "make a", [&](PassBuilder& p) { a = p.write(a, Access::ComputeWrite); }, no_op);
    g.add_compute_pass(
        "a to b",
        [&](PassBuilder& p) {
            p.read(a, Access::ComputeRead);
            b = p.write(b, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "b to c",
        [&](PassBuilder& p) {
            p.read(b, Access::ComputeRead);
            c = p.write(c, Access::ComputeWrite);
        },
        no_op);
    g.add_compute_pass(
        "c to out",
        [&](PassBuilder& p) {
            p.read(c, Access::ComputeRead);
            o = p.write(o, Access::ComputeWrite);
        },
        no_op);
    Plan plan = g.compile();
    auto pa = *plan.placement(a), pb = *plan.placement(b), pc = *plan.placement(c);
    auto overlap = [](const MemoryPlacement& x, const MemoryPlacement& y) {
        return x.block == y.block && x.offset < y.offset + y.size && y.offset < x.offset + x.size;
    };
    EXPECT_FALSE(overlap(pa, pb)) << plan.describe();  // a and b are alive together in "a to b"
    EXPECT_FALSE(overlap(pb, pc));
    EXPECT_TRUE(overlap(pa, pc)) << "a is dead when c is born: c should reuse a's memory\n" << plan.describe();
    EXPECT_LT(plan.transient_memory_bytes(), VkDeviceSize((1 << 20) + (1 << 16) + (1 << 18)));
    // c's first write waits for a's last reader, whose memory it takes over.
    auto alias = barriers_on(plan.pass("b to c").barriers, "c");
    ASSERT_EQ(alias.size(), 1u) << plan.describe();
    EXPECT_EQ(alias[0].src_stages, kCompute);
}

TEST(PlanErrors, StaleHandlesAndWrongAccessesAreRejectedWithNames) {
    Graph g;
    auto t = g.create_buffer({64, "t"});
    auto old = t;
    g.add_compute_pass(
        "writer", [&](PassBuilder& b) { t = b.write(t, Access::ComputeWrite); }, no_op);
    try {
        g.add_compute_pass(
            "stale reader", [&](PassBuilder& b) { b.read(old, Access::ComputeRead); }, no_op);
        FAIL() << "reading a stale version must fail";
    } catch (const Error& e) {
        EXPECT_EQ(e.kind(), ErrorKind::InvalidGraph);
        EXPECT_NE(std::string(e.what()).find("stale reader"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'t'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(g.add_compute_pass(
                     "bad", [&](PassBuilder& b) { b.read(t, Access::ComputeWrite); }, no_op),
                 Error);
    EXPECT_THROW(g.add_compute_pass(
                     "graphics in compute", [&](PassBuilder& b) { b.read(t, Access::VertexRead); }, no_op),
                 Error);
    EXPECT_THROW(g.add_raster_pass(
                     "no attachments", [&](PassBuilder& b) { b.read(t, Access::VertexRead); }, no_op),
                 Error);
    Plan plan = Graph().compile();
    EXPECT_THROW(plan.execute(), Error);  // no device
}
