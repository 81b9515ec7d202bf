import { resolve } from 'node:path';
import { defineConfig } from 'vitest/config';

// The viewer, plus two pages for tests/web/: the benchmark and the layer stories.
// Relative base: the bundle works wherever pslam-server mounts web/dist, with no network access.
export default defineConfig({
  base: './',
  build: {
    outDir: 'dist',
    emptyOutDir: true,
    target: 'es2022',
    sourcemap: true,
    chunkSizeWarningLimit: 600,
    rollupOptions: {
      input: {
        main: resolve(__dirname, 'index.html'),
        bench: resolve(__dirname, 'bench.html'),
        stories: resolve(__dirname, 'stories.html'),
      },
    },
  },
  server: {
    // `npm run dev` against a local pslam-server (default port 8080).
    proxy: {
      '/api': { target: process.env.PSLAM_SERVER ?? 'http://127.0.0.1:8080', ws: true },
    },
  },
  test: {
    include: ['test/**/*.test.ts'],
    environment: 'node',
  },
});
