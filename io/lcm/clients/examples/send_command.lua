-- Sends saccaded one signed command:
-- lua5.2 send_command.lua URL KEY_FILE pause|resume|reset|fovea X Y Z (docs/LCM.md).
-- HMAC-SHA256 (luaossl, Debian's lua-luaossl) with the key of KEY_FILE over every byte of the
-- encoded command_t before its last 32, which it fills.
local lcm = require('lcm')
local hmac = require('openssl.hmac')
local rand = require('openssl.rand')
local saccade = require('saccade')

local url, key_file, kind = arg[1], arg[2], arg[3]
if not kind then
  io.stderr:write('usage: lua5.2 send_command.lua URL KEY_FILE pause|resume|reset|fovea X Y Z\n')
  os.exit(2)
end
local hex = io.open(key_file):read('*a'):gsub('%s+$', '')
assert(#hex == 64, key_file .. ': not a command key (64 hexadecimal digits)')
local key = hex:gsub('..', function(h) return string.char(tonumber(h, 16)) end)

local m = saccade.command_t:new()
m.utime = os.time() * 1000000  -- microseconds since the epoch (whole seconds suffice)
-- Lua's clock has whole seconds: a random sequence tells apart two alike commands of a second.
local r = rand.bytes(4)
m.sequence = ((r:byte(1) % 128) * 256 + r:byte(2)) * 65536 + r:byte(3) * 256 + r:byte(4)
m.kind = ({pause = saccade.command_t.PAUSE, resume = saccade.command_t.RESUME,
           reset = saccade.command_t.RESET, fovea = saccade.command_t.SET_FOVEA})[kind]
assert(m.kind, 'unknown command ' .. kind)
m.fovea = {tonumber(arg[4] or 0), tonumber(arg[5] or 0), tonumber(arg[6] or 0)}
m.model = ''
m.signature = {}
for i = 1, 32 do m.signature[i] = 0 end

local bytes = m:encode()
local body = bytes:sub(1, #bytes - 32)
local lc = lcm.lcm.new(url)
lc:publish('SACCADE_COMMAND', body .. hmac.new(key, 'sha256'):final(body))
print('sent ' .. kind .. ', signed')
