#include "app/gui/view_cache.h"

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

void ViewCache::keep(const Key& key, Renderer& renderer, size_t boxes, size_t boxes_total) {
    if (!picture_) picture_ = std::make_unique<Texture>();
    renderer.copy_to_texture(key.rect, Texture::Content::Colour, *picture_);  // nearest: shown 1:1
    if (boxes < boxes_total && !goes_on(key)) {  // the first share: the depth the next ones draw over
        if (!depth_) depth_ = std::make_unique<Texture>();
        renderer.copy_to_texture(key.rect, Texture::Content::Depth, *depth_);
    }
    key_ = key;
    boxes_in_picture_ = boxes;
    boxes_total_ = boxes_total;
}

}  // namespace accelviz
