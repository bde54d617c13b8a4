#include "app/gui/view_cache.h"

#include <algorithm>

#include "app/gl/renderer.h"

namespace accelviz {

bool ViewCache::draw(const Key& key, Renderer& renderer) {
    if (!holds(key) || drawing_on()) return false;
    // The picture covers the rectangle pixel for pixel (nearest texels, no blending).
    renderer.draw_image(*picture_, key.rect);
    last_frame_full_ = false;
    ++hits_;
    return true;
}

ViewCache::Share ViewCache::plan_frame(const Key& key, bool keepable, size_t boxes_total, bool opaque) const {
    Share share;
    if (!keepable) return share;
    share.goes_on = holds(key) && drawing_on();
    share.keep = share.goes_on || last_full_ms_ >= worth_keeping_ms;  // the last full draw was slow
    if (share.goes_on || (share.keep && opaque && boxes_total > boxes_per_frame)) {
        share.first = share.goes_on ? boxes_in_picture_ : 0;
        share.count = boxes_per_frame;
    }
    return share;
}

void ViewCache::finish_frame(const Key& key, const Share& share, size_t boxes_total, Renderer& renderer) {
    last_frame_full_ = !share.goes_on;
    if (!share.keep) {
        forget();
        return;
    }
    const size_t boxes = share.count == SIZE_MAX ? boxes_total : std::min(share.first + share.count, boxes_total);
    if (!picture_) picture_ = std::make_unique<Texture>();
    renderer.copy_to_texture(key.rect, Texture::Content::Colour, *picture_);  // nearest: shown 1:1
    if (boxes < boxes_total && !share.goes_on) {  // the first share: the depth the next ones draw over
        if (!depth_) depth_ = std::make_unique<Texture>();
        renderer.copy_to_texture(key.rect, Texture::Content::Depth, *depth_);
    }
    key_ = key;
    boxes_in_picture_ = boxes;
    boxes_total_ = boxes_total;
}

}  // namespace accelviz
