// Starts `psh view` for the tests and stops it: the binary is $PSH_BIN or
// target/release/psh; its URL is read from its first line on stdout.
import { spawn } from "node:child_process";
import { readFileSync } from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

export const root = path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
export const psh = process.env.PSH_BIN || path.join(root, "target/release/psh");

// `psh view` with `args`; resolves to { url, child } once it prints its URL (the
// precomputation before it takes seconds), rejects if it exits first or within `ms`.
export function startView(args, ms = 600_000) {
  return new Promise((resolve, reject) => {
    const child = spawn(psh, ["view", "--port", "0", ...args], { stdio: ["ignore", "pipe", "inherit"] });
    let out = "";
    const timer = setTimeout(() => { child.kill(); reject(new Error("psh view printed no URL")); }, ms);
    child.stdout.on("data", (d) => {
      out += d;
      const m = /http:\/\/[^\s]+/.exec(out);
      if (m) { clearTimeout(timer); resolve({ url: m[0], child }); }
    });
    child.on("exit", (code) => { clearTimeout(timer); reject(new Error(`psh view exited with ${code}`)); });
  });
}

// Resident memory of process `pid` in MiB (Linux /proc).
export function rssMiB(pid) {
  const m = /VmRSS:\s+(\d+) kB/.exec(readFileSync(`/proc/${pid}/status`, "utf8"));
  return m ? Number(m[1]) / 1024 : NaN;
}

// Stops the server started by startView.
export function stopView(child) {
  child.removeAllListeners("exit");
  child.kill("SIGTERM");
}
