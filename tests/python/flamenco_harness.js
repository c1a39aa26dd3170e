// Runs a Flamenco job type's compileJob in node, with a small stand-in of the authoring API
// Flamenco gives job types (author.Task/Command, path, print), and prints the tasks.
const fs = require("fs");
const vm = require("vm");
const nodePath = require("path");

const tasks = [];
const author = {
    Task(name, type) {
        const t = { name, type, commands: [], dependencies: [] };
        t.addCommand = c => t.commands.push(c);
        t.addDependency = d => t.dependencies.push(d.name);
        return t;
    },
    Command(name, parameters) { return { name, parameters }; },
};
const job = {
    name: "shot",
    settings: { frames: "1-6", chunk_size: 2, render_output_root: "/renders",
                render_output_path: "/renders/shot/######", blendfile: "/shots/shot.blend" },
    addTask: t => tasks.push(t),
};
const ctx = { author, path: { join: nodePath.join, dirname: nodePath.dirname,
                               basename: nodePath.basename },
              print: () => {}, job };
vm.createContext(ctx);
vm.runInContext(fs.readFileSync(process.argv[2], "utf8") + "\ncompileJob(job);", ctx);
for (const t of tasks) { delete t.addCommand; delete t.addDependency; }
if (!ctx.JOB_TYPE && !vm.runInContext("typeof JOB_TYPE", ctx)) throw "no JOB_TYPE";
console.log(JSON.stringify({ label: vm.runInContext("JOB_TYPE.label", ctx), tasks }));
