// SPDX-License-Identifier: Apache-2.0
//
// Flamenco custom job type: an animation rendered with the PhotonMap Blender add-on.
//
// The first frame is rendered alone and saves the photon maps and irradiance cache
// (scene.photonmap.save_photon_maps); the other frames, in chunks, depend on it and load
// them (load_photon_maps, with photon_maps_mismatch = 'rebuild': a frame whose scene
// differs from the first frame's, the camera aside, builds its own). A camera-only
// animation thus traces its photons once, and its low-frequency noise stays still.
//
// Install: copy this file into the `scripts` directory beside the Flamenco Manager
// executable and restart the Manager; it appears as "PhotonMap (Blender)" in the add-on's
// job types. Every Worker's Blender needs the PhotonMap extension (see the README, "Farms").

const JOB_TYPE = {
    label: "PhotonMap (Blender)",
    description: "Render an animation with PhotonMap: photon maps built once, reused by every frame.",
    settings: [
        { key: "frames", type: "string", required: true,
          eval: "f'{C.scene.frame_start}-{C.scene.frame_end}'",
          evalInfo: { showLinkButton: true, description: "Scene frame range" },
          description: "Frames to render, e.g. '1-30' or '3, 5-10'; the first builds the photon maps" },
        { key: "chunk_size", type: "int32", default: 1, propargs: { min: 1 }, visible: "submission",
          description: "Frames per render task after the first" },
        { key: "render_output_root", type: "string", subtype: "dir_path", required: true,
          visible: "submission", description: "Directory of the job's frames and photon maps" },
        { key: "render_output_path", type: "string", subtype: "file_path", editable: false,
          eval: "str(Path(abspath(settings.render_output_root), jobname, '######'))",
          description: "Final file path of the frames" },
        { key: "blendfile", type: "string", required: true, visible: "web",
          description: "Path of the Blend file to render" },
    ],
};

// Python run by Blender before rendering: PhotonMap as the engine, multilayer EXR output,
// and where the photon maps go.
function setupExpr(mode, mapsPath) {
    const p = JSON.stringify(mapsPath);
    const lines = [
        "import bpy",
        "s = bpy.context.scene",
        "s.render.engine = 'PHOTONMAP'",
        "s.render.image_settings.media_type = 'MULTI_LAYER_IMAGE'",
        "s.render.image_settings.file_format = 'OPEN_EXR_MULTILAYER'",
    ];
    if (mode == "save") {
        lines.push(`s.photonmap.save_photon_maps = ${p}`);
    } else {
        lines.push(`s.photonmap.load_photon_maps = ${p}`);
        lines.push("s.photonmap.photon_maps_mismatch = 'rebuild'");
    }
    return lines.join("; ");
}

// The frames of a Flamenco frame list ("1-10", "3, 5-10, 47"), in order.
function parseFrames(spec) {
    const out = [];
    for (const part of String(spec).split(",")) {
        const t = part.trim();
        if (t == "") continue;
        const m = t.match(/^(-?\d+)\s*(?:-|\.\.)\s*(-?\d+)$/);
        if (m) {
            const a = parseInt(m[1]), b = parseInt(m[2]);
            if (b < a) throw `frame range '${t}' ends before it starts`;
            for (let f = a; f <= b; f++) out.push(f);
        } else if (/^-?\d+$/.test(t)) {
            out.push(parseInt(t));
        } else {
            throw `cannot read frame '${t}' of '${spec}'`;
        }
    }
    if (out.length == 0) throw `no frames in '${spec}'`;
    return out;
}

// Runs of consecutive frames, at most `size` each, as Blender frame arguments.
function chunks(frames, size) {
    const out = [];
    let run = [];
    for (const f of frames) {
        if (run.length > 0 && (f != run[run.length - 1] + 1 || run.length >= size)) {
            out.push(run);
            run = [];
        }
        run.push(f);
    }
    if (run.length > 0) out.push(run);
    return out.map(r => r.length == 1 ? `${r[0]}` : `${r[0]}-${r[r.length - 1]}`);
}

function renderTask(name, settings, outputPath, expr, frames) {
    const task = author.Task(name, "blender");
    task.addCommand(author.Command("blender-render", {
        exe: "{blender}",
        exeArgs: "{blenderArgs}",
        argsBefore: [],
        blendfile: settings.blendfile,
        args: [
            "--python-expr", expr,
            "--render-output", outputPath,
            "--render-format", "OPEN_EXR_MULTILAYER",
            "--render-frame", frames.replace("-", ".."),
        ],
    }));
    return task;
}

function compileJob(job) {
    const settings = job.settings;
    const outputPath = settings.render_output_path;
    const mapsPath = path.join(path.dirname(outputPath), "photon_maps.pmaps");
    const frames = parseFrames(settings.frames);
    const first = renderTask("photon-maps", settings, outputPath,
                             setupExpr("save", mapsPath), `${frames[0]}`);
    job.addTask(first);
    for (const c of chunks(frames.slice(1), Math.max(1, settings.chunk_size || 1))) {
        const task = renderTask(`frames-${c}`, settings, outputPath, setupExpr("load", mapsPath), c);
        task.addDependency(first);
        job.addTask(task);
    }
}
