// A minimal WebSocket client (RFC 6455) for the DevTools protocol on 127.0.0.1: text messages
// only, no extensions. Node 18 (Debian 12's) has no WebSocket of its own, and no npm package
// is wanted for the one connection web/test/playground.mjs makes.
import crypto from 'node:crypto';
import http from 'node:http';

/** Opens `url` (ws://host:port/path); resolves to {send(text), close(), onmessage} once upgraded. */
export function openSocket(url) {
  const { hostname, port, pathname } = new URL(url);
  const key = crypto.randomBytes(16).toString('base64');
  return new Promise((resolve, reject) => {
    const req = http.request({
      host: hostname, port, path: pathname,
      headers: { Connection: 'Upgrade', Upgrade: 'websocket', 'Sec-WebSocket-Version': '13', 'Sec-WebSocket-Key': key },
    });
    req.on('error', reject);
    req.on('response', (res) => reject(new Error(`${url}: HTTP ${res.statusCode} instead of a WebSocket upgrade`)));
    req.on('upgrade', (res, socket, head) => {
      const accept = crypto.createHash('sha1').update(key + '258EAFA5-E914-47DA-95CA-C5AB0DC85B11').digest('base64');
      if (res.headers['sec-websocket-accept'] !== accept) {
        reject(new Error(`${url}: bad Sec-WebSocket-Accept`));
        return;
      }
      const client = { onmessage: () => {}, send: (text) => socket.write(frame(0x1, Buffer.from(text, 'utf8'))), close: () => socket.end(frame(0x8, Buffer.alloc(0))) };
      let buffer = head;
      let message = [];
      socket.on('data', (chunk) => {
        buffer = Buffer.concat([buffer, chunk]);
        for (;;) {
          if (buffer.length < 2) return;
          const fin = buffer[0] & 0x80;
          const opcode = buffer[0] & 0x0f;
          let length = buffer[1] & 0x7f;
          let offset = 2;
          if (length === 126) {
            if (buffer.length < 4) return;
            length = buffer.readUInt16BE(2);
            offset = 4;
          } else if (length === 127) {
            if (buffer.length < 10) return;
            length = Number(buffer.readBigUInt64BE(2));
            offset = 10;
          }
          if (buffer.length < offset + length) return;
          const payload = buffer.subarray(offset, offset + length);
          buffer = buffer.subarray(offset + length);
          if (opcode === 0x9) socket.write(frame(0xa, payload)); // ping: pong
          else if (opcode === 0x8) socket.end();
          else if (opcode === 0x1 || opcode === 0x0) {
            message.push(payload);
            if (fin) {
              const text = Buffer.concat(message).toString('utf8');
              message = [];
              client.onmessage({ data: text });
            }
          }
        }
      });
      resolve(client);
    });
    req.end();
  });
}

// One final frame from the client: masked, as RFC 6455 requires of clients.
function frame(opcode, payload) {
  const mask = crypto.randomBytes(4);
  const length = payload.length;
  const header = length < 126 ? Buffer.alloc(2) : length < 65536 ? Buffer.alloc(4) : Buffer.alloc(10);
  header[0] = 0x80 | opcode;
  if (length < 126) header[1] = 0x80 | length;
  else if (length < 65536) {
    header[1] = 0x80 | 126;
    header.writeUInt16BE(length, 2);
  } else {
    header[1] = 0x80 | 127;
    header.writeBigUInt64BE(BigInt(length), 2);
  }
  const masked = Buffer.alloc(length);
  for (let i = 0; i < length; ++i) masked[i] = payload[i] ^ mask[i & 3];
  return Buffer.concat([header, mask, masked]);
}
