// The 3D view's kept picture (ViewCache): a frame drawn from it is the frame a full
// draw gives, pixel for pixel; a change to what the view shows draws it again; a view
// drawn a share of its boxes per frame ends as the one-frame picture; and a view that
// draws from more than the key holds (the split view, the slice) is never drawn from it.
#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/geometry/scene.h"

namespace accelviz {
namespace {

struct CachedApp {
    std::unique_ptr<HeadlessApp> app;
    AppState state;
};

/// A headless window on the teapot with its BVH's boxes, keeping every full draw
/// (the window keeps only slow ones: see ViewCache::kWorthKeepingMs). With `state`,
/// that state's camera and settings (not the scene's default view).
CachedApp open_teapot(const AppState* state = nullptr) {
    CachedApp out;
    auto app = HeadlessApp::create(320, 240);
    EXPECT_TRUE(app) << app.error();
    if (!app) return out;
    out.app = std::move(*app);
    if (state) {
        out.state = *state;
    } else {
        out.state.scene = "builtin:teapot?n=4";
        out.state.view.draw_with = DrawWith::Raster;
    }
    auto loaded = load_and_build(out.state.scene, out.state.accel);
    EXPECT_TRUE(loaded) << loaded.error();
    if (!loaded) return out;
    out.app->session().set_scene(out.state, *loaded, /*keep_camera=*/state != nullptr);
    out.app->session().view_cache.worth_keeping_ms = 0;
    return out;
}

Image draw(CachedApp& c, bool draw_ui = true) {
    FrameInput input;
    input.draw_ui = draw_ui;
    c.app->draw(c.state, input);
    return c.app->read_colour();
}

/// The frame a window that never keeps a picture draws for `state` after `frames`
/// frames. (Made after the cached app is gone: one headless app at a time.)
Image fresh_frame(const AppState& state, int frames, bool draw_ui) {
    CachedApp fresh = open_teapot(&state);
    if (!fresh.app) return {};
    fresh.app->session().view_cache.worth_keeping_ms = 1e30;
    Image out;
    for (int i = 0; i < frames; ++i) out = draw(fresh, draw_ui);
    return out;
}

TEST(ViewCache, AFrameFromTheKeptPictureIsTheFullFrame) {
    AppState state;
    Image full_frame, kept_frame, view_alone, view_alone_kept;
    {
        CachedApp c = open_teapot();
        ASSERT_TRUE(c.app);
        ViewCache& cache = c.app->session().view_cache;
        full_frame = draw(c);  // a full draw, kept
        EXPECT_EQ(cache.hits(), 0u);
        draw(c);  // nothing changed: from the picture (the panels settle: ImGui sizes a window one frame late)
        EXPECT_EQ(cache.hits(), 1u);
        kept_frame = draw(c);
        EXPECT_EQ(cache.hits(), 2u);
        // The 3D view alone, over the whole frame: another rectangle, drawn again, then kept.
        view_alone = draw(c, false);
        EXPECT_EQ(cache.hits(), 2u);
        view_alone_kept = draw(c, false);
        EXPECT_EQ(cache.hits(), 3u);
        state = c.state;
    }
    EXPECT_EQ(kept_frame.pixels, fresh_frame(state, 3, true).pixels);
    EXPECT_EQ(view_alone.pixels, view_alone_kept.pixels);
    EXPECT_EQ(view_alone_kept.pixels, fresh_frame(state, 1, false).pixels);
}

TEST(ViewCache, WhatTheViewShowsChangingDrawsItAgain) {
    struct Change {
        const char* what;
        AppState state;
        Image drawn, kept;
    };
    std::vector<Change> changes;
    Image before;
    {
        CachedApp c = open_teapot();
        ASSERT_TRUE(c.app);
        ViewCache& cache = c.app->session().view_cache;
        before = draw(c, false);
        draw(c, false);
        ASSERT_EQ(cache.hits(), 1u);
        auto change = [&](const char* what) {
            const uint64_t hits = cache.hits();
            Change ch{what, c.state, draw(c, false), {}};
            EXPECT_EQ(cache.hits(), hits) << what << ": drawn in full";
            ch.kept = draw(c, false);
            EXPECT_EQ(cache.hits(), hits + 1) << what << ": then kept";
            changes.push_back(std::move(ch));
        };
        c.state.overlay.level_max = 2;
        change("overlay levels");
        c.state.view.background = Rgb{200, 40, 40};
        change("background");
        c.state.camera->eye = c.state.camera->eye * 1.3;
        change("camera");
        c.state.view.draw_with = DrawWith::RayCast;
        change("draw with");
    }
    const Image* previous = &before;
    for (const Change& ch : changes) {
        EXPECT_NE(ch.drawn.pixels, previous->pixels) << ch.what << " changes the picture";
        EXPECT_EQ(ch.kept.pixels, ch.drawn.pixels) << ch.what;
        EXPECT_EQ(ch.drawn.pixels, fresh_frame(ch.state, 1, false).pixels) << ch.what;
        previous = &ch.drawn;
    }
}

TEST(ViewCache, ABigStillViewDrawnAShareOfItsBoxesPerFrameEndsAsTheOneFramePicture) {
    AppState state;
    Image first_part, finished, from_picture;
    int parts = 0;
    size_t boxes = 0;
    {
        CachedApp c = open_teapot();
        ASSERT_TRUE(c.app);
        ViewCache& cache = c.app->session().view_cache;
        cache.boxes_per_frame = 100;
        first_part = draw(c, false);
        parts = 1;
        boxes = c.app->session().overlay_boxes->size();
        while (cache.drawing_on() && parts < 100) {
            finished = draw(c, false);
            ++parts;
        }
        EXPECT_FALSE(cache.drawing_on());
        EXPECT_EQ(cache.hits(), 0u) << "every frame so far drew a share of the boxes";
        from_picture = draw(c, false);
        EXPECT_EQ(cache.hits(), 1u) << "then the whole picture";
        state = c.state;
    }
    ASSERT_GT(boxes, 500u) << "the teapot's BVH has enough boxes to take several frames";
    EXPECT_EQ(size_t(parts), (boxes + 99) / 100) << "a frame per 100 boxes";
    const Image one_frame = fresh_frame(state, 1, false);
    EXPECT_EQ(finished.pixels, one_frame.pixels) << "the last share completes the one-frame picture";
    EXPECT_EQ(from_picture.pixels, one_frame.pixels);
    EXPECT_NE(first_part.pixels, one_frame.pixels) << "the first frame holds only the first boxes";
}

TEST(ViewCache, APictureUnderWayIsDroppedWhenTheViewGoesAway) {
    // Else the window, which draws on at once while a picture is under way, would spin.
    CachedApp c = open_teapot();
    ASSERT_TRUE(c.app);
    ViewCache& cache = c.app->session().view_cache;
    cache.boxes_per_frame = 100;
    draw(c);
    ASSERT_TRUE(cache.drawing_on());
    c.app->session().lecture.on = true;
    c.app->session().lecture.blank = true;  // lecture mode's black screen (B)
    draw(c);
    EXPECT_FALSE(cache.drawing_on());
}

TEST(ViewCache, AViewDrawnFromMoreThanTheSettingsIsNeverKept) {
    CachedApp c = open_teapot();
    ASSERT_TRUE(c.app);
    ViewCache& cache = c.app->session().view_cache;
    c.state.view.mode = ViewMode::Split;
    draw(c);
    draw(c);
    EXPECT_EQ(cache.hits(), 0u) << "split view";
    c.state.view.mode = ViewMode::View3D;
    c.state.view.slice = true;
    draw(c);
    draw(c);
    EXPECT_EQ(cache.hits(), 0u) << "inside/outside slice";
}

}  // namespace
}  // namespace accelviz
