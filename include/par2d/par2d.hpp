// Everything an embedding engine needs: scene model, loader, one-shot render, persistent Renderer, image files.
#pragma once

#include "par2d/alpha_outline.hpp"
#include "par2d/image_io.hpp"
#include "par2d/isa.hpp"
#include "par2d/render.hpp"
#include "par2d/renderer.hpp"
#include "par2d/scene.hpp"
#include "par2d/scene_write.hpp"
#include "par2d/status.hpp"
#include "par2d/types.hpp"
#include "par2d/version.hpp"
