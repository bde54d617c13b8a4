#include "app/gui/view_cache.h"

#include "app/gl/renderer.h"

namespace accelviz {

bool ViewCache::draw(const Key& key, Renderer& renderer) {
    if (!key_ || !(*key_ == key) || !picture_ || picture_->empty()) return false;
    // The picture covers the rectangle pixel for pixel (nearest texels, no blending).
    renderer.draw_image(*picture_, key.rect);
    ++hits_;
    return true;
}

void ViewCache::keep(const Key& key, Renderer& renderer, double last_full_ms) {
    if (last_full_ms < worth_keeping_ms || key.rect.empty()) {
        key_.reset();
        return;
    }
    if (!picture_) picture_ = std::make_unique<Texture>();
    picture_->upload(renderer.read_colour(key.rect));  // nearest: shown 1:1
    key_ = key;
}

}  // namespace accelviz
