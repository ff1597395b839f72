# The Cycles settings every cross-check render shares (README.md here): CPU,
# SPP samples of seed SEED, nothing that biases or filters (no adaptive
# sampling, denoising, clamping, glossy blur or light threshold; caustics
# on), a box pixel filter one pixel wide, and nuld's path depth: nuld's max
# depth d counts hits, Cycles counts bounces after the first.


def configure_cycles(scene, spp, seed, depth):
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = int(spp)
    cycles.seed = int(seed)
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.sample_clamp_direct = 0
    cycles.sample_clamp_indirect = 0
    cycles.blur_glossy = 0
    cycles.light_sampling_threshold = 0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    for attr in ["max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                 "transparent_max_bounces", "volume_bounces"]:
        setattr(cycles, attr, depth - 1)
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0


def write_exr(scene, path):
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = path
