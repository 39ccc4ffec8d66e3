-- cluster.lua — wrk script for `make bench`'s cluster figures (bench/perf/cluster.py): GETs tiles of
-- several stored meshes through nginx, each URL once (so nginx's tile cache never answers).
-- TOCHER_MESH_IDS (comma-separated ids), TOCHER_TILE_Z, TOCHER_TILE_FORMAT (default png),
-- TOCHER_WRK_THREADS (wrk's -t: each thread has its own Lua state and cannot count the others);
-- thread t of T asks for tiles t, t+T, t+2T, ... of the sequence mesh = k mod M, tile = k div M.
local ids = {}
for id in string.gmatch(os.getenv("TOCHER_MESH_IDS"), "[^,]+") do table.insert(ids, id) end
local z = tonumber(os.getenv("TOCHER_TILE_Z"))
local fmt = os.getenv("TOCHER_TILE_FORMAT") or "png"
local side = 2 ^ z
local threads = {}

function setup(thread)
  thread:set("id", #threads)
  table.insert(threads, thread)
end

function init(args)
  k = id
  stride = tonumber(os.getenv("TOCHER_WRK_THREADS"))
end

function request()
  local m, t = k % #ids, math.floor(k / #ids)
  k = k + stride
  local x, y = t % side, math.floor(t / side) % side
  return wrk.format("GET", string.format("/v1/meshes/%s/tiles/%d/%d/%d.%s", ids[m + 1], z, x, y, fmt))
end

done = function(summary, latency, requests)
  io.write(string.format("WRKJSON {\"requests\": %d, \"duration_us\": %d, \"errors\": %d, \"non2xx\": %d, \"p50_us\": %d, \"p90_us\": %d, \"p99_us\": %d, \"max_us\": %d}\n",
    summary.requests, summary.duration, summary.errors.connect + summary.errors.read + summary.errors.write + summary.errors.timeout,
    summary.errors.status, latency:percentile(50), latency:percentile(90), latency:percentile(99), latency.max))
end
