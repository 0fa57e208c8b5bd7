-- Prints where saccaded sees each instance, and each track's state changes:
-- lua5.2 print_instances.lua [URL] [FRAMES]. Act on TRACKING and RE-ACQUIRED only (docs/LCM.md).
local lcm = require('lcm')
local saccade = require('saccade')

-- mug for /var/lib/saccade/models/mug.pcd; a spec such as synthetic:target as it is.
local function short_name(model_name)
  local name = model_name:match('([^/]*)$')
  name = name:match('^(.+)%.[^.]*$') or name
  if name == '' then return model_name end
  return name
end

local lc = lcm.lcm.new(arg[1] or 'udpm://239.255.76.67:7667?ttl=0')
local frames = tonumber(arg[2] or '0')  -- 0: until Ctrl-C
local seen = 0
local states = {}  -- track id -> its last state
lc:subscribe('SACCADE_DETECTIONS', function(channel, data)
  local d = saccade.detections_t.decode(data)
  for _, i in ipairs(d.instances) do
    local name = short_name(i.model_name)
    if i.track_id >= 0 and states[i.track_id] ~= i.track_state_name then
      print(string.format('%s #%d: %s -> %s', name, i.track_id, states[i.track_id] or 'NEW',
                          i.track_state_name))
      states[i.track_id] = i.track_state_name
    end
    -- centroid: where the object is (trans is the model's origin)
    print(string.format('%s #%d %s at (%.3f, %.3f, %.3f) m in %s, confidence %.2f', name,
                        i.track_id, i.track_state_name, i.centroid[1], i.centroid[2],
                        i.centroid[3], d.frame, i.confidence))
  end
  io.stdout:flush()
  if d.num_instances > 0 then seen = seen + 1 end
end)
while frames == 0 or seen < frames do lc:handle() end
