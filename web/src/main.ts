// Bootstrap only: build the app into #app and start it.
import './styles.css';
import { App } from './ui/app';

const root = document.getElementById('app');
if (root) {
  const app = new App(root);
  app.start();
  // A read-only handle for the browser tests and for debugging from the console.
  (window as unknown as { pslam: unknown }).pslam = { app };
}
